// Reader for dexcloth recordings (docs/recording-format.md): recording.json + frames.bin.
// Plain ES module with no dependencies, so it runs in the browser and in Node.

const FILE_MAGIC = 'DXCLREC1';
const FILE_HEADER_BYTES = 16;
const RECORD_MAGIC = 0x52465844; // "DXFR"
const RECORD_FIXED_BYTES = 44;
const LITTLE_ENDIAN_HOST = new Uint8Array(new Uint32Array([1]).buffer)[0] === 1;

/** Bytes of one frame record without contacts or patches. */
export function fixedRecordBytes(header) {
  const vertices = header.cloths.reduce((n, c) => n + c.vertex_count, 0);
  return RECORD_FIXED_BYTES + 12 * vertices + 28 * header.rigid_shapes.length;
}

/**
 * Indexes the records of frames.bin. Throws an Error naming the problem for a corrupt or
 * truncated file; an unfinished recording (header.complete false) is read up to its last whole
 * record, as the C++ reader's recover mode does.
 * @returns {{offsets: number[], contacts: number[], patches: number[]}}
 */
export function indexFrames(header, buffer) {
  const view = new DataView(buffer);
  const magic = new TextDecoder().decode(new Uint8Array(buffer, 0, Math.min(8, buffer.byteLength)));
  if (buffer.byteLength < FILE_HEADER_BYTES) throw new Error('frames.bin: truncated: shorter than its 16-byte file header');
  if (magic !== FILE_MAGIC) throw new Error('frames.bin: not a dexcloth frames file (bad magic)');
  const version = view.getUint32(8, true);
  if (version !== 1) throw new Error(`frames.bin: unsupported frames version ${version}`);

  const fixed = fixedRecordBytes(header);
  const offsets = [], contacts = [], patches = [];
  let offset = FILE_HEADER_BYTES;
  while (offset + 40 <= buffer.byteLength) {
    const where = `frames.bin: frame ${offsets.length} at byte ${offset}`;
    if (view.getUint32(offset, true) !== RECORD_MAGIC) throw new Error(`${where}: corrupt (bad record magic)`);
    const bytes = view.getUint32(offset + 4, true);
    const index = view.getUint32(offset + 8, true);
    const c = view.getUint32(offset + 12, true);
    const p = view.getUint32(offset + 16, true);
    if (index !== offsets.length) throw new Error(`${where}: corrupt (record says frame ${index})`);
    if (bytes !== fixed + 36 * c + 40 * p) throw new Error(`${where}: corrupt (record of ${bytes} bytes, header implies ${fixed + 36 * c + 40 * p})`);
    if (offset + bytes > buffer.byteLength) break; // partial last record
    offsets.push(offset);
    contacts.push(c);
    patches.push(p);
    offset += bytes;
  }
  const stray = buffer.byteLength - offset;
  if (header.complete && (offsets.length !== header.frame_count || stray !== 0)) {
    throw new Error(`frames.bin: truncated or corrupt: header says ${header.frame_count} frames, ` +
      `file holds ${offsets.length} whole frames (+${stray} stray bytes)`);
  }
  return { offsets, contacts, patches };
}

// Float32 values starting at `byteOffset` (a view into the buffer on little-endian hosts).
function floats(buffer, byteOffset, count) {
  if (LITTLE_ENDIAN_HOST) return new Float32Array(buffer, byteOffset, count);
  const view = new DataView(buffer, byteOffset, count * 4);
  const out = new Float32Array(count);
  for (let i = 0; i < count; ++i) out[i] = view.getFloat32(4 * i, true);
  return out;
}

/** A loaded recording with random access to its frames. */
export class Recording {
  constructor(header, buffer) {
    this.header = header;
    this.buffer = buffer;
    this.index = indexFrames(header, buffer);
  }

  get frameCount() { return this.index.offsets.length; }

  /**
   * Frame k: time [s], step wall time [ms], per-cloth positions (Float32Array |V|·3),
   * rigid poses (Float32Array 7·S: x y z qx qy qz qw), contacts (9·C: position, normal, force)
   * and patches (10·P: centre, quaternion, size).
   */
  frame(k) {
    const base = this.index.offsets[k];
    if (base === undefined) throw new Error(`frame ${k} out of range [0, ${this.frameCount})`);
    const view = new DataView(this.buffer);
    let at = base + 40;
    const cloths = this.header.cloths.map((c) => {
      const x = floats(this.buffer, at, 3 * c.vertex_count);
      at += 12 * c.vertex_count;
      return x;
    });
    const s = this.header.rigid_shapes.length;
    const poses = floats(this.buffer, at, 7 * s);
    at += 28 * s;
    const contacts = floats(this.buffer, at, 9 * this.index.contacts[k]);
    at += 36 * this.index.contacts[k];
    const patches = floats(this.buffer, at, 10 * this.index.patches[k]);
    return {
      t: view.getFloat64(base + 24, true),
      stepMs: view.getFloat64(base + 32, true),
      cloths, poses, contacts, patches,
    };
  }
}

/** Fetches `<base>recording.json` and its frames file and returns a Recording. */
export async function loadRecording(base) {
  const headerResponse = await fetch(`${base}recording.json`, { cache: 'no-store' });
  if (!headerResponse.ok) throw new Error(`${base}recording.json: HTTP ${headerResponse.status}`);
  const header = await headerResponse.json();
  if (header.format !== 'dexcloth-recording' || header.version !== 1) {
    throw new Error(`${base}recording.json: not a dexcloth recording (version 1)`);
  }
  const framesResponse = await fetch(`${base}${header.frames_file}`, { cache: 'no-store' });
  if (!framesResponse.ok) throw new Error(`${base}${header.frames_file}: HTTP ${framesResponse.status}`);
  return new Recording(header, await framesResponse.arrayBuffer());
}
