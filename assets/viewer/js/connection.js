// The connection to `isorad view`: the WebSocket that streams the solution
// (hello, mesh, light, status), reconnected every second when it drops,
// its binary message decoders, and the control requests.
//
// Binary messages are little-endian; a 16-byte header of four u32:
//   mesh  (kind 1): version, V, T,  then f32 positions[3V], u32 indices[3T]
//   light (kind 2): mesh_version, V, 0, then f32 radiance[3V], f32 lux[V]

/** Message kind of a binary mesh. */
export const KIND_MESH = 1;
/** Message kind of a binary light. */
export const KIND_LIGHT = 2;

const HEADER_BYTES = 16;
const LITTLE_ENDIAN_HOST = new Uint8Array(new Uint32Array([1]).buffer)[0] === 1;

/**
 * `count` little-endian f32 (or u32 when `unsigned`) at `offset` of `buffer`,
 * copied into a fresh typed array.
 * @param {ArrayBuffer} buffer
 * @param {number} offset bytes
 * @param {number} count
 * @param {boolean} unsigned
 */
function readArray(buffer, offset, count, unsigned) {
  const Type = unsigned ? Uint32Array : Float32Array;
  if (LITTLE_ENDIAN_HOST && offset % 4 === 0) {
    return new Type(buffer.slice(offset, offset + 4 * count));
  }
  const view = new DataView(buffer, offset, 4 * count);
  const out = new Type(count);
  for (let i = 0; i < count; i++) {
    out[i] = unsigned ? view.getUint32(4 * i, true) : view.getFloat32(4 * i, true);
  }
  return out;
}

/**
 * Decodes a binary message.
 * @param {ArrayBuffer} buffer
 * @returns {{type:'mesh', version:number, vertexCount:number,
 *   triangleCount:number, positions:Float32Array, indices:Uint32Array}
 *   | {type:'light', meshVersion:number, vertexCount:number,
 *   radiance:Float32Array, illuminance:Float32Array}}
 * @throws {Error} on a short, inconsistent or unknown message
 */
export function decodeBinary(buffer) {
  if (buffer.byteLength < HEADER_BYTES) throw new Error('binary message shorter than its header');
  const header = new DataView(buffer, 0, HEADER_BYTES);
  const kind = header.getUint32(0, true);
  const a = header.getUint32(4, true);
  const v = header.getUint32(8, true);
  const t = header.getUint32(12, true);
  if (kind === KIND_MESH) {
    const expected = HEADER_BYTES + 12 * v + 12 * t;
    if (buffer.byteLength !== expected) {
      throw new Error(`mesh message of ${buffer.byteLength} bytes, expected ${expected}`);
    }
    const indices = readArray(buffer, HEADER_BYTES + 12 * v, 3 * t, true);
    for (let i = 0; i < indices.length; i++) {
      if (indices[i] >= v) throw new Error(`mesh index ${indices[i]} ≥ vertex count ${v}`);
    }
    return {
      type: 'mesh',
      version: a,
      vertexCount: v,
      triangleCount: t,
      positions: readArray(buffer, HEADER_BYTES, 3 * v, false),
      indices,
    };
  }
  if (kind === KIND_LIGHT) {
    const expected = HEADER_BYTES + 16 * v;
    if (buffer.byteLength !== expected) {
      throw new Error(`light message of ${buffer.byteLength} bytes, expected ${expected}`);
    }
    return {
      type: 'light',
      meshVersion: a,
      vertexCount: v,
      radiance: readArray(buffer, HEADER_BYTES, 3 * v, false),
      illuminance: readArray(buffer, HEADER_BYTES + 12 * v, v, false),
    };
  }
  throw new Error(`unknown binary message kind ${kind}`);
}

/**
 * Decodes a text message: JSON with a `type` ("hello", "status").
 * @param {string} text
 * @returns {object}
 */
export function decodeText(text) {
  const message = JSON.parse(text);
  if (!message || typeof message.type !== 'string') throw new Error('text message without a type');
  return message;
}

/** The WebSocket address of the page's server. */
export function socketUrl() {
  return (location.protocol === 'https:' ? 'wss' : 'ws') + '://' + location.host + '/ws';
}

/**
 * Opens the stream and keeps it open: on a drop, retries every
 * `retryMs` ms. Every decoded message goes to `handlers.message(m)`;
 * `handlers.connected(bool)` reports the connection; decode errors go to
 * `handlers.error(e)`.
 * @param {{message:(m:object)=>void, connected:(up:boolean)=>void,
 *   error:(e:Error)=>void}} handlers
 * @param {number} [retryMs]
 * @returns {{close:()=>void}}
 */
export function connect(handlers, retryMs = 1000) {
  let socket = null;
  let timer = null;
  let closed = false;

  const retry = () => {
    if (closed || timer !== null) return;
    timer = setTimeout(() => {
      timer = null;
      open();
    }, retryMs);
  };

  const receive = (event) => {
    try {
      const m = typeof event.data === 'string' ? decodeText(event.data) : decodeBinary(event.data);
      handlers.message(m);
    } catch (e) {
      handlers.error(e);
    }
  };

  function open() {
    if (closed) return;
    try {
      socket = new WebSocket(socketUrl());
    } catch (e) {
      handlers.error(e);
      retry();
      return;
    }
    socket.binaryType = 'arraybuffer';
    socket.onopen = () => handlers.connected(true);
    socket.onmessage = receive;
    socket.onclose = () => {
      socket = null;
      handlers.connected(false);
      retry();
    };
    socket.onerror = () => {
      // A close event follows; it retries.
    };
  }

  open();
  return {
    close() {
      closed = true;
      if (timer !== null) clearTimeout(timer);
      if (socket) socket.close();
    },
  };
}

/**
 * POSTs an empty body to /control/<action> (pause, resume, stop).
 * @param {string} action
 * @returns {Promise<void>} rejects on a network error or a non-2xx answer
 */
export async function control(action) {
  const response = await fetch('/control/' + action, { method: 'POST' });
  if (!response.ok) throw new Error(`${action}: HTTP ${response.status}`);
}

/**
 * GETs /probe at a point and normal; resolves to the parsed JSON either way
 * (a 4xx answer is `{error: "..."}`), with `ok` telling which.
 * @param {{x:number,y:number,z:number,nx:number,ny:number,nz:number}} request
 * @returns {Promise<{ok:boolean, body:object}>}
 */
export async function probe(request) {
  const query = new URLSearchParams();
  for (const key of ['x', 'y', 'z', 'nx', 'ny', 'nz']) query.set(key, String(request[key]));
  const response = await fetch('/probe?' + query.toString());
  let body;
  try {
    body = await response.json();
  } catch (e) {
    body = { error: `HTTP ${response.status}` };
  }
  return { ok: response.ok, body };
}
