// The guidance's "add a node here" markers (www/editor-guide.js): where their full labels
// would cover each other, the less important ones show as a small "+".
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { fullLabels } from '../../www/editor-guide.js';

test('a label that would cover one shown before it is made small; apart, all are full', () => {
  const size = { w: 150, h: 30 };
  // Three close together (the second on the first, the third just beside it), one far off.
  const at = [{ x: 400, y: 300 }, { x: 420, y: 310 }, { x: 549, y: 329 }, { x: 100, y: 100 }];
  assert.deepEqual(fullLabels(at, size), [true, false, false, true]);
  // A label exactly its width away, or its height, covers nothing.
  assert.deepEqual(fullLabels([{ x: 0, y: 0 }, { x: 150, y: 0 }, { x: 0, y: 30 }], size), [true, true, true]);
  // The order decides: the first of two close ones keeps its label.
  assert.deepEqual(fullLabels([at[1], at[0]], size), [true, false]);
  assert.deepEqual(fullLabels([], size), []);
});
