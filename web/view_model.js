// Parses the view model splat-view --serve sends for a file (lib/serve/encode_view_model.h):
// "SKVIEW1\0", u32 LE JSON length, JSON header, padding to 4 bytes, the arrays.
export function parseViewModel(buffer) {
  const bytes = new Uint8Array(buffer);
  const magic = new TextDecoder().decode(bytes.subarray(0, 7));
  if (magic !== 'SKVIEW1') throw new Error('not a view model');
  const length = new DataView(buffer).getUint32(8, true);
  const header = JSON.parse(new TextDecoder().decode(bytes.subarray(12, 12 + length)));
  const base = (12 + length + 3) & ~3;
  const arrays = {};
  for (const [name, a] of Object.entries(header.arrays)) {
    const offset = base + a.offset;
    if (a.type === 'f32') arrays[name] = new Float32Array(buffer, offset, a.bytes / 4);
    else if (a.type === 'u32') arrays[name] = new Uint32Array(buffer, offset, a.bytes / 4);
    else arrays[name] = new Uint8Array(buffer, offset, a.bytes);
  }
  header.center = header.bounds.slice(0, 3);
  header.radius = header.bounds[3];
  header.box = header.box ?? null;  // [min x, y, z, max x, y, z], or none: framed by the sphere
  return { header, arrays };
}
