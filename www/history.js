// Undo and redo over layout documents: a list of snapshots and a cursor. Documents are kept
// as given (the editor never changes one in place), so a step costs one reference.

export class History {
  /** @param {number} limit the most snapshots kept; the oldest are dropped */
  constructor(limit = 500) {
    this.limit = limit;
    this.clear(null);
  }

  /** Forgets everything; `doc` becomes the only state. */
  clear(doc) {
    this.states = [{ doc, label: 'start' }];
    this.index = 0;
  }

  get current() {
    return this.states[this.index].doc;
  }

  get canUndo() {
    return this.index > 0;
  }

  get canRedo() {
    return this.index < this.states.length - 1;
  }

  /** The label of the step undo would take back, or null. */
  get undoLabel() {
    return this.canUndo ? this.states[this.index].label : null;
  }

  get redoLabel() {
    return this.canRedo ? this.states[this.index + 1].label : null;
  }

  /** Records `doc` after the current state; what could be redone is dropped. */
  push(doc, label = 'edit') {
    this.states.length = this.index + 1;
    this.states.push({ doc, label });
    if (this.states.length > this.limit) this.states.shift();
    this.index = this.states.length - 1;
  }

  /**
   * The last `count` states up to the current one ({ doc, label }, the current last), for
   * saving: what could be redone is left out.
   */
  recent(count) {
    return this.states.slice(Math.max(0, this.index + 1 - count), this.index + 1);
  }

  /** Continues from saved states (as `recent` gave them; the last is current). */
  resume(states) {
    this.states = states.slice(-this.limit);
    this.index = this.states.length - 1;
  }

  /** Steps back; returns the document then current, or null when there is nothing to undo. */
  undo() {
    if (!this.canUndo) return null;
    this.index--;
    return this.current;
  }

  redo() {
    if (!this.canRedo) return null;
    this.index++;
    return this.current;
  }
}
