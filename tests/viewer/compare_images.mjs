// Compares the viewer's screenshot with splat-view's render of the same camera:
//   node compare_images.mjs REFERENCE.png OTHER.png
// Both are 8-bit RGB(A) PNGs over splat-view's background colour; a pixel is in an image's mask
// when any channel differs from that colour by more than 2 levels. Prints one JSON line:
// {"iou": mask IoU, "psnr": dB over the pixels both masks hold (8-bit RGB), "reference_pixels",
// "other_pixels", "both"}.
import { readFileSync } from 'node:fs';
import { inflateSync } from 'node:zlib';

export function readPng(path) {
  const data = readFileSync(path);
  if (data.readUInt32BE(0) !== 0x89504e47) throw new Error(`${path}: not a PNG`);
  let pos = 8, width = 0, height = 0, bpp = 0;
  const idat = [];
  while (pos < data.length) {
    const length = data.readUInt32BE(pos);
    const kind = data.toString('latin1', pos + 4, pos + 8);
    const body = data.subarray(pos + 8, pos + 8 + length);
    if (kind === 'IHDR') {
      width = body.readUInt32BE(0);
      height = body.readUInt32BE(4);
      if (body[8] !== 8 || (body[9] !== 2 && body[9] !== 6) || body[12] !== 0)
        throw new Error(`${path}: only 8-bit RGB or RGBA PNGs without interlacing`);
      bpp = body[9] === 2 ? 3 : 4;
    } else if (kind === 'IDAT') {
      idat.push(body);
    }
    pos += 12 + length;
  }
  const raw = inflateSync(Buffer.concat(idat));
  const stride = width * bpp;
  const out = new Uint8Array(width * height * 3);
  let prev = new Uint8Array(stride), cur = new Uint8Array(stride);
  for (let y = 0; y < height; ++y) {
    const type = raw[y * (stride + 1)];
    const row = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    for (let x = 0; x < stride; ++x) {
      const a = x >= bpp ? cur[x - bpp] : 0, b = prev[x], c = x >= bpp ? prev[x - bpp] : 0;
      let p = 0;
      if (type === 1) p = a;
      else if (type === 2) p = b;
      else if (type === 3) p = (a + b) >> 1;
      else if (type === 4) {
        const pa = Math.abs(b - c), pb = Math.abs(a - c), pc = Math.abs(a + b - 2 * c);
        p = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      cur[x] = (row[x] + p) & 255;
    }
    for (let x = 0; x < width; ++x)
      for (let k = 0; k < 3; ++k) out[(y * width + x) * 3 + k] = cur[x * bpp + k];
    [prev, cur] = [cur, prev];
  }
  return { width, height, rgb: out };
}

const BACKGROUND = [38, 42, 46];  // splat-view's default background, linear 0.0194 0.0232 0.0273

function mask(img) {
  const m = new Uint8Array(img.width * img.height);
  for (let i = 0; i < m.length; ++i)
    for (let k = 0; k < 3; ++k)
      if (Math.abs(img.rgb[3 * i + k] - BACKGROUND[k]) > 2) { m[i] = 1; break; }
  return m;
}

// The comparison, when run as a program (readPng is also imported by other scripts).
function main() {
  const [refPath, otherPath] = process.argv.slice(2);
  const ref = readPng(refPath), other = readPng(otherPath);
  if (ref.width !== other.width || ref.height !== other.height) {
    console.log(JSON.stringify({ error: `sizes differ: ${ref.width}x${ref.height} and ` +
                                        `${other.width}x${other.height}` }));
    process.exit(1);
  }
  const a = mask(ref), b = mask(other);
  let both = 0, either = 0, na = 0, nb = 0, se = 0;
  for (let i = 0; i < a.length; ++i) {
    na += a[i]; nb += b[i];
    if (a[i] || b[i]) ++either;
    if (a[i] && b[i]) {
      ++both;
      for (let k = 0; k < 3; ++k) se += (ref.rgb[3 * i + k] - other.rgb[3 * i + k]) ** 2;
    }
  }
  const mse = both ? se / (3 * both) : 0;
  const psnr = mse > 0 ? 10 * Math.log10(255 * 255 / mse) : 99;
  console.log(JSON.stringify({ iou: either ? both / either : 1, psnr, reference_pixels: na,
                               other_pixels: nb, both }));
}

if (process.argv[1].endsWith('compare_images.mjs')) main();
