// A promise-based client over the worker that owns the wasm core (worker.js). Each request
// gets an id; its reply settles the matching promise. The protocol is in protocol.js.
import { MSG } from './protocol.js';

/**
 * An error reported by the worker: `message` is for the user, `kind` and `culprits` for the
 * page (what the error is and which elements it names; see protocol.js).
 */
export class CoreError extends Error {
  constructor(message, { fatal = false, kind = fatal ? 'internal' : 'other', culprits = null } = {}) {
    super(message);
    this.name = 'CoreError';
    this.fatal = fatal;
    this.kind = kind;
    this.culprits = culprits;
  }
}

export class CoreClient {
  /** @param {URL|string} workerUrl the module worker's script */
  constructor(workerUrl = new URL('./worker.js', import.meta.url)) {
    this.workerUrl = workerUrl;
    this.worker = null;
    this.nextId = 1;
    /** id → { resolve, reject } of the requests in flight */
    this.pending = new Map();
    /** The last mesh and layout the worker accepted, to send again to a fresh worker. */
    this.replay = null;
    this.listeners = new Set();
  }

  /**
   * Reads a mesh file in the worker and makes it the current mesh.
   * @param {ArrayBuffer} bytes the file's contents; transferred, unusable afterwards
   * @param {string} name the file's name; its extension picks the format
   * @param {{repairs?: {keep_largest?: boolean, fill_holes?: number}}} options repairs the
   *   user asked for (cli.md, "Repairs the user asks for")
   * @returns {Promise<{summary: object, positions: Float32Array, triangles: Uint32Array}>}
   */
  load(bytes, name, { quiet = false, replaying = false, repairs = null } = {}) {
    // A copy stays here, so a restarted worker gets the mesh again (see restart()).
    const copy = replaying ? null : bytes.slice(0);
    return this.request(MSG.LOAD, { bytes, name, ...(repairs ? { repairs } : {}) }, [bytes]).then((result) => {
      if (!replaying) this.replay = { mesh: { bytes: copy, name, repairs }, layout: null };
      if (!quiet) this.emit({ type: 'mesh', name });
      return result;
    });
  }

  /**
   * Places a layout on the worker's current mesh.
   * @param {string} text the layout file (JSON, format v1)
   * @returns {Promise<object>} the LayoutView of protocol.js
   */
  setLayout(text, { quiet = false, replaying = false } = {}) {
    if (this.replay && !replaying) this.replay.layout = null; // the worker drops its layout first
    return this.request(MSG.SET_LAYOUT, { text }).then(
      (result) => {
        if (this.replay && !replaying) this.replay.layout = text;
        if (!quiet) this.emit({ type: 'layout', text, view: result });
        return result;
      },
      (err) => {
        if (!quiet) this.emit({ type: 'layout-error', text, error: err });
        throw err;
      },
    );
  }

  /**
   * Calls `listener(event)` after every change of the worker's mesh or layout, whoever asked
   * for it: { type: 'mesh', name } | { type: 'layout', text, view } |
   * { type: 'layout-error', text, error } (the worker then has no layout). A new
   * layout drops the worker's parameterizations. Returns a function that unsubscribes.
   */
  onChange(listener) {
    this.listeners.add(listener);
    return () => this.listeners.delete(listener);
  }

  emit(event) {
    for (const listener of this.listeners) {
      try {
        listener(event);
      } catch (err) {
        console.error(err);
      }
    }
  }

  /**
   * Starts a parameterization of the placed layout (iteration 0).
   * @param {{align?: boolean, chart?: 'quad'|'rect'|'unit'|null}} options
   */
  startParam(options) {
    return this.request(MSG.PARAM_START, { options });
  }

  /** One chart-optimization iteration; resolves to its IterationStats. */
  stepParam() {
    return this.request(MSG.PARAM_STEP);
  }

  /** The final solve; resolves to the ParamResult of protocol.js. */
  finishParam() {
    return this.request(MSG.PARAM_FINISH);
  }

  /** Keeps the active run as `name`. */
  keepParam(name) {
    return this.request(MSG.PARAM_KEEP, { name });
  }

  /** Makes the run kept as `name` active (the active one kept as `previous`). */
  useParam(name, previous = null) {
    return this.request(MSG.PARAM_USE, { name, previous });
  }

  /**
   * Extracts the quad mesh of the active run; resolves to the QuadResult of protocol.js.
   * @param {{edge_length?: number}} options
   */
  remesh(options) {
    return this.request(MSG.REMESH, { options });
  }

  /**
   * A file of the active run: 'param-obj', 'cut-obj', 'quad-obj', 'quad-ply' or 'quad-glb'.
   * @returns {Promise<{bytes: ArrayBuffer, mime: string}>}
   */
  exportFile(what) {
    return this.request(MSG.EXPORT, { what });
  }

  /**
   * The cross field of the current mesh and its singularities; resolves to the CrossField of
   * protocol.js.
   * @param {{featureAngle?: number}} options
   */
  crossField(options) {
    return this.request(MSG.FIELD, { options });
  }

  /**
   * Proposes a layout for the current mesh; resolves to { text, field, seconds, note } (protocol.js).
   * @param {{patches?: number, featureAngle?: number}} options
   */
  suggestLayout(options) {
    return this.request(MSG.SUGGEST, { options });
  }

  /**
   * Which of the proposals made apart to keep; resolves to its index or null (protocol.js).
   * @param {Array<{judged: object|null, curves: number}|null>} candidates
   */
  pickSuggestion(candidates) {
    return this.request(MSG.PICK_SUGGESTION, { candidates });
  }

  /**
   * The last step of proposals made apart (protocol.js FINISH_SUGGESTION); resolves to
   * { layout, judged }.
   * @param {string|null} text the kept proposal's layout, null where none was made
   * @param {{hausdorff: number, score: number, folded: number}|null} judged
   * @param {{patches?: number, featureAngle?: number}} options
   */
  finishSuggestion(text, judged, options) {
    return this.request(MSG.FINISH_SUGGESTION, { text, judged, options });
  }

  /**
   * Another client on a worker of its own with this one's mesh (none while it has none),
   * for work that runs beside this one's; `terminate()` it when done.
   * @returns {Promise<CoreClient>}
   */
  async helper() {
    const helper = new CoreClient(this.workerUrl);
    const mesh = this.replay?.mesh;
    if (mesh) await helper.load(mesh.bytes.slice(0), mesh.name, { quiet: true, replaying: true, repairs: mesh.repairs });
    return helper;
  }

  /**
   * Throws the worker away (requests in flight are rejected with `reason`) and starts a
   * fresh one with the current mesh and layout sent again, so work can go on; its runs are
   * lost. Used to cancel a long solve and after a crash of the core.
   * @returns {Promise<void>} settles when the mesh and layout are back in place
   */
  restart(reason = 'cancelled') {
    this.terminate(reason);
    const replay = this.replay;
    if (!replay) return Promise.resolve();
    // `replay` stays as it is, so a restart during this one sends the same again.
    const mesh = replay.mesh.bytes.slice(0);
    const options = { quiet: true, replaying: true, repairs: replay.mesh.repairs };
    // Both sent at once: a request made after restart() then queues behind them in the
    // worker (it handles messages in order), instead of slipping in between.
    const loaded = this.load(mesh, replay.mesh.name, options);
    const placed = replay.layout == null ? null : this.setLayout(replay.layout, options);
    return Promise.allSettled([loaded, placed]).then(() => {});
  }

  /** Sends one request; resolves to its `result`, rejects with a CoreError. */
  request(type, args = {}, transfer = []) {
    const worker = this.ensureWorker();
    const id = this.nextId++;
    return new Promise((resolve, reject) => {
      this.pending.set(id, { resolve, reject });
      worker.postMessage({ id, type, ...args }, transfer);
    });
  }

  /** Stops the worker; requests in flight are rejected. */
  terminate(reason = 'the quadlay core was stopped') {
    this.worker?.terminate();
    this.worker = null;
    for (const { reject } of this.pending.values()) reject(new CoreError(reason, { fatal: true, kind: 'stopped' }));
    this.pending.clear();
  }

  ensureWorker() {
    if (this.worker) return this.worker;
    const worker = new Worker(this.workerUrl, { type: 'module', name: 'quadlay-core' });
    worker.onmessage = (event) => this.settle(event.data);
    // A worker that fails to start or throws outside a request: fail what is in flight, and
    // start a fresh worker on the next request.
    worker.onerror = (event) => {
      event.preventDefault();
      this.terminate(`the quadlay core stopped: ${event.message || 'its worker failed to start (is www/pkg built? npm run build)'}`);
    };
    worker.onmessageerror = () => this.terminate('the quadlay core sent a message that could not be read');
    this.worker = worker;
    return worker;
  }

  settle({ id, result, error, kind, culprits, fatal }) {
    const entry = this.pending.get(id);
    if (!entry) return;
    this.pending.delete(id);
    if (error === undefined) {
      entry.resolve(result);
    } else {
      entry.reject(new CoreError(error, { fatal, kind, culprits }));
      if (fatal) this.restart(error);
    }
  }
}
