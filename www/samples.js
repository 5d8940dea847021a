// The sample meshes the page offers (copied from shared/meshes into www/samples by the
// build), with the sample layout (www/layouts) shown on it. The first is loaded when the
// page opens.
export const SAMPLES = [
  { file: 'fandisk.obj', title: 'Fandisk', note: 'mechanical part with sharp features', layout: 'layouts/fandisk-features.layout.json' },
  { file: 'mushroom.obj', title: 'Mushroom', note: 'disk with one boundary loop', layout: 'layouts/mushroom-grid.layout.json' },
  { file: 'bunny_28k.obj', title: 'Bunny 28k', note: 'organic, closed', layout: 'layouts/bunny-ears.layout.json' },
  { file: 'eight.obj', title: 'Eight', note: 'genus 2', layout: 'layouts/eight-rims.layout.json' },
  { file: 'bunny_1k8.obj', title: 'Bunny 1.8k', note: 'coarse bunny' },
  { file: 'nefertiti.obj', title: 'Nefertiti', note: 'small relief with boundary' },
  { file: 'elephant_44k.obj', title: 'Elephant', note: 'genus 3, 89k triangles' },
];
