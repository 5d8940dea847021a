// The module Web Worker that owns the wasm core. It keeps one `Session` (the current mesh)
// between messages, so later work (layout, solve) can run on it without sending the mesh
// again. The protocol is stated in protocol.js.
import init, { Session } from './pkg/quadlay.js';
import { MSG } from './protocol.js';

/** The current mesh; replaced only by a successful load. */
let session = null;
/** The wasm instantiation, started by the first message. */
let ready = null;

/** One function per message type: args → { result, transfer }. */
const handlers = {
  [MSG.LOAD]({ bytes, name }) {
    const next = new Session(new Uint8Array(bytes), name);
    session?.free();
    session = next;
    const positions = session.positions();
    const triangles = session.triangles();
    return {
      result: { summary: session.summary(), positions, triangles },
      transfer: [positions.buffer, triangles.buffer],
    };
  },
  [MSG.SET_LAYOUT]({ text }) {
    if (!session) throw new Error('load a mesh before a layout');
    return { result: session.setLayout(text) };
  },
};

// Set before anything is awaited: messages that arrive while the wasm is still being
// instantiated would otherwise be lost.
self.onmessage = async (event) => {
  const { id, type, ...args } = event.data;
  try {
    ready ??= init().catch((err) => {
      ready = null; // let the next message try again
      throw new Error(`could not start the quadlay core: ${err?.message || err}`);
    });
    await ready;
    const handler = handlers[type];
    if (!handler) throw new Error(`unknown message type '${type}'`);
    const { result, transfer = [] } = handler(args);
    self.postMessage({ id, result }, transfer);
  } catch (err) {
    // A trap leaves the instance's memory in an unknown state: ask for a fresh worker.
    const fatal = err instanceof WebAssembly.RuntimeError;
    const message = err?.message || String(err);
    self.postMessage({
      id,
      error: fatal ? `internal error in the quadlay core (${message}); it was restarted` : message,
      fatal,
    });
  }
};
