// Drives headless Chromium through puppeteer-core: serves page.html, the .glb and illum's EXR
// frame of it from a local HTTP server, runs the page's check, writes three.png and prints
// the per-channel errors as JSON. Exit 1 when the mean relative error of a channel over the
// light-mapped surfaces exceeds --bound, 2 on bad arguments. Called by run.sh (which installs the pinned packages).
import http from 'node:http';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import puppeteer from 'puppeteer-core';

const here = path.dirname(fileURLToPath(import.meta.url));
const args = Object.fromEntries(
  process.argv.slice(2).reduce((pairs, a, i, all) => (a.startsWith('--') ? [...pairs, [a.slice(2), all[i + 1]]] : pairs), [])
);
for (const key of ['glb', 'exr', 'out', 'width', 'height', 'chromium', 'bound'])
  if (args[key] === undefined) {
    console.error(`render.mjs: --${key} is required`);
    process.exit(2);
  }
const width = Number(args.width), height = Number(args.height), bound = Number(args.bound);
const lightmap = args.lightmap !== 'off';

const files = { '/': path.join(here, 'page.html'), '/illum-lightmap.js': path.join(here, 'illum-lightmap.js'),
  '/scene.glb': args.glb, '/illum.exr': args.exr };
const types = { '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript' };
const server = http.createServer((request, response) => {
  const url = decodeURIComponent(new URL(request.url, 'http://localhost').pathname);
  if (url === '/favicon.ico') {
    response.writeHead(204).end();
    return;
  }
  let file = files[url];
  if (!file && url.startsWith('/node_modules/') && !url.includes('..')) file = path.join(here, url);
  if (!file || !fs.existsSync(file)) {
    response.writeHead(404).end();
    return;
  }
  response.writeHead(200, { 'Content-Type': types[path.extname(file)] ?? 'application/octet-stream' });
  fs.createReadStream(file).pipe(response);
});
await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));

const browser = await puppeteer.launch({
  executablePath: args.chromium,
  headless: true,
  // WebGL2 without a GPU: ANGLE on SwiftShader (software Vulkan), allowed explicitly.
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'],
});
let status = 0;
try {
  const page = await browser.newPage();
  page.on('console', (m) => console.error(`page: ${m.text()}`));
  page.on('pageerror', (e) => console.error(`page error: ${e.message}`));
  await page.goto(`http://127.0.0.1:${server.address().port}/`);
  await page.waitForFunction('window.pageReady === true', { timeout: 60000 });
  const result = await page.evaluate((o) => window.runCheck(o), { width, height, lightmap });
  fs.writeFileSync(path.join(args.out, 'three.png'), Buffer.from(result.png.split(',')[1], 'base64'));
  delete result.png;
  result.chromium = await browser.version();
  result.bound_mean_relative = bound;
  const worst = Math.max(...result.surfaces.mean_relative);
  result.pass = worst <= bound;
  console.log(JSON.stringify(result, null, 2));
  if (!result.pass) status = 1;
} catch (e) {
  console.error(`render.mjs: ${e.message}`);
  status = 1;
} finally {
  await browser.close();
  server.close();
}
process.exit(status);
