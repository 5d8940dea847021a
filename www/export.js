// Downloads: a file made in the worker (protocol.js EXPORT) handed to the browser through a
// Blob URL, named after the mesh.

/** What each export is: the worker's `what`, the file name's tail, a label. */
export const EXPORTS = {
  'quad-obj': { suffix: '.quads.obj', label: 'Quads OBJ', title: 'the quad mesh as OBJ' },
  'quad-ply': { suffix: '.quads.ply', label: 'Quads PLY', title: 'the quad mesh as binary PLY' },
  'quad-glb': { suffix: '.quads.glb', label: 'Quads GLB', title: 'the quad mesh as GLB (each quad as two triangles)' },
  'param-obj': { suffix: '.param.obj', label: 'UV OBJ', title: 'the input mesh with one vt per triangle corner (as --param-out)' },
  'cut-obj': { suffix: '.refined.param.obj', label: 'Refined UV OBJ', title: 'the mesh refined along the layout curves, one vt per triangle corner' },
};

/** The file name for export `what` of the mesh called `meshName`. */
export function exportName(meshName, what) {
  const base = (meshName || 'mesh').replace(/\.[^.]*$/, '');
  return base + EXPORTS[what].suffix;
}

/**
 * Offers bytes as a download.
 * @param {ArrayBuffer} bytes
 * @param {string} name
 * @param {string} mime
 */
export function download(bytes, name, mime = 'application/octet-stream') {
  const url = URL.createObjectURL(new Blob([bytes], { type: mime }));
  const a = document.createElement('a');
  a.href = url;
  a.download = name;
  a.style.display = 'none';
  document.body.append(a);
  a.click();
  a.remove();
  // The download has its own copy once started.
  setTimeout(() => URL.revokeObjectURL(url), 60_000);
}
