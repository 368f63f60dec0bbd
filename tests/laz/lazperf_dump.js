// Decodes a LAZ file with laz-perf (LASzip compiled to WebAssembly, the npm package "laz-perf")
// and writes its point records, as an uncompressed LAS file would hold them, to OUT.
// Usage: NODE_PATH=<dir with node_modules/laz-perf> node lazperf_dump.js IN.laz OUT.bin
// Prints "count record_length format" on stdout; exits 1 with laz-perf's message on failure.
'use strict';
const fs = require('fs');
const { createLazPerf } = require('laz-perf');

async function main() {
  const [input, output] = process.argv.slice(2);
  const file = fs.readFileSync(input);
  const lp = await createLazPerf();
  lpModule = lp;
  const filePtr = lp._malloc(file.length);
  lp.HEAPU8.set(file, filePtr);
  const laszip = new lp.LASZip();
  try {
    laszip.open(filePtr, file.length);
    const count = laszip.getCount();
    const length = laszip.getPointLength();
    const out = Buffer.alloc(count * length);
    const pointPtr = lp._malloc(length);
    for (let i = 0; i < count; ++i) {
      laszip.getPoint(pointPtr);
      out.set(lp.HEAPU8.subarray(pointPtr, pointPtr + length), i * length);
    }
    fs.writeFileSync(output, out);
    console.log(`${count} ${length} ${laszip.getPointFormat()}`);
  } finally {
    laszip.delete();
  }
}

let lpModule = null;

// laz-perf is built without exception catching: a C++ exception arrives as the address of the
// thrown object. For a std::runtime_error (libc++, wasm32) the message pointer follows the vtable.
function message(e) {
  const m = /^(\d+) - Exception catching is disabled/.exec(String(e && e.message ? e.message : e));
  if (!m || !lpModule) return String(e);
  const heap = lpModule.HEAPU8;
  const at = lpModule.HEAPU32[(Number(m[1]) + 4) >> 2];
  let text = '';
  for (let i = at; i < at + 200 && i < heap.length && heap[i]; ++i) text += String.fromCharCode(heap[i]);
  return 'laz-perf: ' + (text || 'exception at ' + m[1]);
}

main().catch((e) => {
  console.error('lazperf_dump: ' + message(e));
  process.exit(1);
});
