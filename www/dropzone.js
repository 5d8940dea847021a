// Drag-and-drop of mesh files onto the view, with a visible hint while a file is dragged.

/**
 * @param {HTMLElement} zone the element files may be dropped on
 * @param {HTMLElement} hint shown while files are dragged over the zone
 * @param {(file: File) => void} onFile called with the first dropped file
 */
export function initDropZone(zone, hint, onFile) {
  // dragenter/dragleave fire for every child crossed; count them to know when we left.
  let depth = 0;
  const carriesFiles = (event) => Array.from(event.dataTransfer?.types ?? []).includes('Files');
  const show = (on) => { hint.hidden = !on; };

  zone.addEventListener('dragenter', (event) => {
    if (!carriesFiles(event)) return;
    event.preventDefault();
    depth++;
    show(true);
  });
  zone.addEventListener('dragover', (event) => {
    if (!carriesFiles(event)) return;
    event.preventDefault();
    event.dataTransfer.dropEffect = 'copy';
  });
  zone.addEventListener('dragleave', () => {
    depth = Math.max(0, depth - 1);
    if (depth === 0) show(false);
  });
  zone.addEventListener('drop', (event) => {
    if (!carriesFiles(event)) return;
    event.preventDefault();
    depth = 0;
    show(false);
    const file = event.dataTransfer.files[0];
    if (file) onFile(file);
  });

  // A file dropped beside the zone must not make the browser open it instead of the page.
  for (const type of ['dragover', 'drop']) {
    window.addEventListener(type, (event) => {
      if (carriesFiles(event) && !zone.contains(event.target)) {
        event.preventDefault();
        if (event.dataTransfer) event.dataTransfer.dropEffect = 'none';
      }
    });
  }
}
