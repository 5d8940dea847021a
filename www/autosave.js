// Autosave of the layout being drawn, in localStorage, keyed by the mesh (its file name,
// vertex and triangle counts), so a reload or a crashed worker loses nothing: the next visit
// with the same mesh offers to restore it.

const PREFIX = 'quadlay.layout:';

/** The storage key of a mesh. */
export function meshKey(name, summary) {
  return `${PREFIX}${name}:${summary.vertices}:${summary.triangles}`;
}

/** The saved layout of a mesh: { doc, time (ms since 1970) }, or null. */
export function readSaved(key) {
  try {
    const raw = localStorage.getItem(key);
    if (!raw) return null;
    const saved = JSON.parse(raw);
    if (!saved || typeof saved.doc !== 'object' || !Number.isFinite(saved.time)) return null;
    return saved;
  } catch {
    return null;
  }
}

/** Saves `doc` for the mesh; a layout without nodes removes the entry. False if storage failed. */
export function writeSaved(key, doc) {
  try {
    if (!doc?.nodes?.length) localStorage.removeItem(key);
    else localStorage.setItem(key, JSON.stringify({ doc, time: Date.now() }));
    return true;
  } catch {
    return false; // storage full or disabled: the editor keeps working without
  }
}

export function removeSaved(key) {
  try {
    localStorage.removeItem(key);
  } catch {
    // nothing to do
  }
}

/** "14:03" today, "Nov 21, 14:03" on another day. */
export function formatTime(time, now = Date.now()) {
  const d = new Date(time);
  const sameDay = new Date(now).toDateString() === d.toDateString();
  const clock = d.toLocaleTimeString('en-GB', { hour: '2-digit', minute: '2-digit' });
  return sameDay ? clock : `${d.toLocaleDateString('en-US', { month: 'short', day: 'numeric' })}, ${clock}`;
}
