// Autosave of the layout being drawn, in localStorage, keyed by the mesh (its file name,
// vertex and triangle counts), so a reload or a crashed worker loses nothing: the next visit
// with the same mesh offers to restore it. The last steps of the undo history are saved
// with it, so after restoring, Ctrl+Z takes back the last edit, not the whole layout.

import { numberedCounts } from './layout-doc.js';

const PREFIX = 'quadlay.layout:';

/** The storage key of a mesh: its file's counts, whatever the core's refinement made of it. */
export function meshKey(name, summary) {
  const { vertices, triangles } = numberedCounts(summary);
  return `${PREFIX}${name}:${vertices}:${triangles}`;
}

/** How many steps of the undo history are saved with a layout. */
export const SAVED_STEPS = 30;

/**
 * The saved layout of a mesh: { doc, time (ms since 1970), steps }, or null. `steps` are the
 * history's last states ({ doc, label }, the last one `doc`); just [{ doc }] when none were
 * saved.
 */
export function readSaved(key) {
  try {
    const raw = localStorage.getItem(key);
    if (!raw) return null;
    const saved = JSON.parse(raw);
    if (!saved || typeof saved.doc !== 'object' || !Number.isFinite(saved.time)) return null;
    const steps = Array.isArray(saved.steps) && saved.steps.every((s) => s && typeof s.doc === 'object')
      ? saved.steps : [];
    // The current document closes the list, whatever was stored.
    if (!steps.length || JSON.stringify(steps.at(-1).doc) !== JSON.stringify(saved.doc)) steps.push({ doc: saved.doc, label: 'restore' });
    return { doc: saved.doc, time: saved.time, steps };
  } catch {
    return null;
  }
}

/**
 * Saves `doc` for the mesh, with the history's last `steps` ({ doc, label }, ending with
 * `doc`); a layout without nodes removes the entry. False if storage failed.
 */
export function writeSaved(key, doc, steps = []) {
  try {
    if (!doc?.nodes?.length) {
      localStorage.removeItem(key);
      return true;
    }
    try {
      localStorage.setItem(key, JSON.stringify({ doc, time: Date.now(), steps }));
    } catch {
      // Storage full: the layout without its history.
      localStorage.setItem(key, JSON.stringify({ doc, time: Date.now() }));
    }
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
