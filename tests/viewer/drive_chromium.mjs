// Drives headless Chromium over the DevTools protocol (--remote-debugging-pipe: JSON messages
// separated by NUL bytes on file descriptors 3 and 4; no npm package needed) to open the viewer
// page, wait for its first frame, and save the canvas and the page's stats.
//
//   node drive_chromium.mjs --chromium PATH --url URL --width W --height H \
//        [--png CANVAS.png] [--screenshot PAGE.png] [--json OUT.json] [--bench MS] [--eval JS]
//   node drive_chromium.mjs --chromium PATH --width W --height H --jobs JOBS.jsonl
// (--eval: an expression evaluated in the page after the first frame, awaited; its value is
// "eval" in the JSON)
//
// Software GL: SwiftShader through ANGLE. Exit 0 on success; 1 with a message otherwise.
import { spawn } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

const args = {};
for (let i = 2; i < process.argv.length; i += 2) args[process.argv[i].slice(2)] = process.argv[i + 1];
const width = Number(args.width ?? 1280), height = Number(args.height ?? 720);
const profile = mkdtempSync(join(tmpdir(), 'splatkit-chromium-'));

const browser = spawn(args.chromium ?? 'chromium', [
  '--headless=new', '--remote-debugging-pipe', '--no-sandbox', '--no-first-run',
  '--no-default-browser-check', '--disable-extensions', '--disable-background-networking',
  '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist',
  '--force-device-scale-factor=1', `--window-size=${width},${height}`,
  `--user-data-dir=${profile}`, 'about:blank',
], { stdio: ['ignore', 'ignore', 'pipe', 'pipe', 'pipe'] });
let stderr = '';
browser.stdio[2].on('data', (d) => { stderr += d; });

const pending = new Map();
let nextId = 1;
let buffered = Buffer.alloc(0);
browser.stdio[4].on('data', (chunk) => {
  buffered = Buffer.concat([buffered, chunk]);
  let end;
  while ((end = buffered.indexOf(0)) >= 0) {
    const message = JSON.parse(buffered.subarray(0, end).toString());
    buffered = buffered.subarray(end + 1);
    const p = pending.get(message.id);
    if (!p) continue;
    pending.delete(message.id);
    if (message.error) p.reject(new Error(`${p.method}: ${message.error.message}`));
    else p.resolve(message.result);
  }
});

function send(method, params = {}, sessionId) {
  const id = nextId++;
  const message = { id, method, params };
  if (sessionId) message.sessionId = sessionId;
  browser.stdio[3].write(JSON.stringify(message) + '\0');
  return new Promise((resolve, reject) => pending.set(id, { resolve, reject, method }));
}

async function evaluate(session, expression) {
  const r = await send('Runtime.evaluate',
                       { expression, awaitPromise: true, returnByValue: true }, session);
  if (r.exceptionDetails) throw new Error(`page: ${JSON.stringify(r.exceptionDetails).slice(0, 400)}`);
  return r.result.value;
}

function finish(code, message) {
  if (message) console.error(`drive_chromium: ${message}`);
  browser.kill('SIGKILL');
  try { rmSync(profile, { recursive: true, force: true }); } catch { /* best effort */ }
  process.exit(code);
}

const timer = setTimeout(() => finish(1, `timed out; chromium said: ${stderr.slice(-600)}`),
                         Number(args.timeout ?? 90) * 1000);
browser.on('exit', (code) => finish(1, `chromium exited (${code}): ${stderr.slice(-600)}`));

// One page: open `job.url` in a new tab, wait for its first frame, then what the job asks.
async function runJob(job) {
  const { targetId } = await send('Target.createTarget', { url: 'about:blank' });
  const { sessionId } = await send('Target.attachToTarget', { targetId, flatten: true });
  try {
    await send('Emulation.setDeviceMetricsOverride',
               { width, height, deviceScaleFactor: 1, mobile: false }, sessionId);
    await send('Page.enable', {}, sessionId);
    await send('Page.navigate', { url: job.url }, sessionId);
    const stats = await evaluate(sessionId, `new Promise((resolve) => {
        const poll = () => window.viewer ? window.viewer.ready.then(resolve) : setTimeout(poll, 20);
        poll(); })`);
    if (!stats || stats.error) throw new Error(`the page failed: ${stats?.error}`);
    const result = { stats };
    if (job.png) {
      const url = await evaluate(sessionId, 'window.viewer.capture()');
      writeFileSync(job.png, Buffer.from(url.slice(url.indexOf(',') + 1), 'base64'));
    }
    if (job.screenshot) {  // the whole page, controls and stats included
      const shot = await send('Page.captureScreenshot', { format: 'png' }, sessionId);
      writeFileSync(job.screenshot, Buffer.from(shot.data, 'base64'));
    }
    if (job.eval) result.eval = await evaluate(sessionId, job.eval);
    if (job.bench) result.bench = await evaluate(sessionId, `window.viewer.bench(${Number(job.bench)})`);
    result.gl = await evaluate(sessionId, `(() => {
        const gl = document.createElement('canvas').getContext('webgl2');
        const info = gl && gl.getExtension('WEBGL_debug_renderer_info');
        return info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : String(gl && gl.getParameter(gl.RENDERER));
      })()`);
    return result;
  } finally {
    await send('Target.closeTarget', { targetId });
  }
}

// --jobs FILE: one JSON object per line ({"url", "png", "screenshot", "json", "eval", "bench"}),
// all in one browser; else one job from the options.
const jobs = args.jobs
  ? readFileSync(args.jobs, 'utf8').split('\n').filter((l) => l.trim()).map((l) => JSON.parse(l))
  : [{ url: args.url, png: args.png, screenshot: args.screenshot, json: args.json,
       eval: args.eval, bench: args.bench }];
let failed = 0;
for (const job of jobs) {
  let text;
  try {
    text = JSON.stringify(await runJob(job));
  } catch (err) {
    ++failed;
    console.error(`drive_chromium: ${job.url}: ${err.message}`);
    text = JSON.stringify({ error: err.message });
  }
  if (job.json) writeFileSync(job.json, text + '\n'); else console.log(text);
}
clearTimeout(timer);
browser.removeAllListeners('exit');
finish(failed ? 1 : 0);
