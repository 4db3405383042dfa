// End-to-end test of the viewer: `cmkit view` serves a small room with two
// traces on 127.0.0.1; headless Chromium (Debian's, driven by playwright-core)
// opens it, the picture must not be blank, clicking a trace must show its
// contact, and the toggles must work.
//
//   node test/screenshot.mjs CMKIT_BINARY [SCREENSHOT.png]
//
// Exit codes: 0 pass, 1 fail, 77 skipped (no chromium, no node_modules, no
// built viewer, no cmkit binary) with the reason on stderr.
import { spawn, spawnSync } from 'node:child_process';
import { existsSync, mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const SKIP = 77;
const CHROMIUM = '/usr/bin/chromium';
/** A screenshot whose pixel variance is below this shows nothing. */
const MIN_VARIANCE = 20;
/** ...and one with fewer distinct colours than this is not a scene. */
const MIN_COLORS = 16;
/** Seconds the server runs at most (it is stopped as soon as the test ends). */
const SERVER_SECONDS = 120;

const viewerDir = resolve(dirname(fileURLToPath(import.meta.url)), '..');
const cmkit = process.argv[2];
const shotPath = process.argv[3] ?? join(tmpdir(), 'cmkit-viewer-test.png');

function skip(why) {
  console.error(`SKIPPED: ${why}`);
  process.exit(SKIP);
}
if (!cmkit || !existsSync(cmkit)) skip(`no cmkit binary (${cmkit ?? 'not given'})`);
if (!existsSync(CHROMIUM)) skip(`${CHROMIUM} is absent (apt-get install chromium)`);
if (!existsSync(join(viewerDir, 'node_modules', 'playwright-core'))) skip('viewer/node_modules is absent (npm ci --prefix viewer)');
if (!existsSync(join(viewerDir, 'dist', 'index.html'))) {
  const build = spawnSync('npx', ['vite', 'build'], { cwd: viewerDir, stdio: 'inherit' });
  if (build.status !== 0 || !existsSync(join(viewerDir, 'dist', 'index.html'))) skip('cannot build the viewer (npx vite build)');
}
const { chromium } = await import('playwright-core');

// A room of six brushes, a pillar, a door (an entity of its own), and two
// traces through it.
function box([x0, y0, z0], [x1, y1, z1], material = 'textures/base_wall/lfwall27d') {
  const side = (a, b, c, d) => `( ${a} ${b} ${c} ${d} ) ( ( 0.0078125 0 0 ) ( 0 0.0078125 0 ) ) "${material}" 0 0 0\n`;
  return `{\nbrushDef3\n{\n${side(1, 0, 0, -x1)}${side(-1, 0, 0, x0)}${side(0, 1, 0, -y1)}${side(0, -1, 0, y0)}` +
    `${side(0, 0, 1, -z1)}${side(0, 0, -1, z0)}}\n}\n`;
}
const map = 'Version 2\n{\n"classname" "worldspawn"\n' +
  box([-256, -256, -16], [256, 256, 0]) + box([-256, -256, 256], [256, 256, 272]) +
  box([-272, -256, -16], [-256, 256, 272]) + box([256, -256, -16], [272, 256, 272]) +
  box([-256, -272, -16], [256, -256, 272]) + box([-256, 256, -16], [256, 272, 272]) +
  box([-40, -40, 0], [40, 40, 128]) + box([100, 100, 0], [160, 160, 64], 'textures/liquids/water') + '}\n' +
  '{\n"classname" "func_door"\n"name" "door1"\n' + box([180, -60, 0], [196, 60, 128]) + '}\n' +
  '{\n"classname" "info_player_start"\n"name" "start_in_pillar"\n"origin" "0 0 1"\n}\n';
const queries = 'translation trm=box:-16,-16,0,16,16,72 start=-200,-200,8 end=200,200,8\n' +
  'translation trm=point start=-150,150,200 end=-150,150,-100\n';

const work = mkdtempSync(join(tmpdir(), 'cmkit-viewer-test-'));
let server;
let browser;
let failed = false;
function check(ok, what) {
  console.log(`${ok ? 'ok' : 'FAIL'}: ${what}`);
  if (!ok) failed = true;
}
try {
  writeFileSync(join(work, 'room.map'), map);
  writeFileSync(join(work, 'q.txt'), queries);
  const q = spawnSync(cmkit, ['query', join(work, 'room.map'), join(work, 'q.txt'), '--world', '-o', join(work, 'r.txt')]);
  if (q.status !== 0) throw new Error(`cmkit query failed: ${q.stderr}`);

  // The audit finds the player start in the pillar (exit 1: a high finding).
  const audit = spawnSync(cmkit, ['audit', join(work, 'room.map'), '--from', '-200,150,1', '--json', join(work, 'a.json')]);
  if (audit.status !== 1) throw new Error(`cmkit audit gave ${audit.status}: ${audit.stdout}${audit.stderr}`);

  server = spawn(cmkit, ['view', join(work, 'room.map'), '--queries', join(work, 'q.txt'), '--results',
    join(work, 'r.txt'), '--audit', join(work, 'a.json'), '--port', '0', '--exit-after', String(SERVER_SECONDS),
    '--viewer-dir', join(viewerDir, 'dist')], { stdio: ['ignore', 'pipe', 'inherit'] });
  const url = await new Promise((ok, fail) => {
    let out = '';
    server.stdout.on('data', (d) => {
      out += d;
      const m = out.match(/viewer: (http:\/\/127\.0\.0\.1:\d+\/\S*)/);
      if (m) ok(m[1]);
    });
    server.on('exit', (code) => fail(new Error(`cmkit view exited (${code}): ${out}`)));
  });
  check(url.startsWith('http://127.0.0.1:'), `served on loopback: ${url}`);

  // A fresh profile folder (playwright passes it as --user-data-dir).
  browser = await chromium.launchPersistentContext(join(work, 'profile'), {
    executablePath: CHROMIUM,
    headless: true,
    viewport: { width: 1000, height: 640 },
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
      '--enable-unsafe-swiftshader'],
  });
  const page = browser.pages()[0] ?? (await browser.newPage());
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(url);
  await page.waitForSelector('body[data-ready]', { timeout: 60000 });
  check(await page.evaluate(() => document.body.dataset.ready === '1'),
    `scene loaded (${await page.textContent('#status')})`);
  await page.waitForTimeout(500);
  await page.screenshot({ path: shotPath });
  console.log(`screenshot: ${shotPath}`);

  // Pixel statistics of the WebGL canvas.
  const stats = await page.evaluate(() => {
    const src = document.getElementById('view');
    const c = document.createElement('canvas');
    c.width = src.width;
    c.height = src.height;
    const ctx = c.getContext('2d');
    ctx.drawImage(src, 0, 0);
    const px = ctx.getImageData(0, 0, c.width, c.height).data;
    let sum = 0, sq = 0, n = 0;
    const colors = new Set();
    for (let i = 0; i < px.length; i += 4) {
      for (let k = 0; k < 3; ++k) {
        sum += px[i + k];
        sq += px[i + k] * px[i + k];
        ++n;
      }
      colors.add((px[i] << 16) | (px[i + 1] << 8) | px[i + 2]);
    }
    return { variance: sq / n - (sum / n) ** 2, colors: colors.size };
  });
  check(stats.variance > MIN_VARIANCE, `picture not blank (variance ${stats.variance.toFixed(1)})`);
  check(stats.colors >= MIN_COLORS, `picture has ${stats.colors} colours`);

  // Click the first trace on the canvas, then pick the second from the list.
  const at = await page.evaluate(() => window.cmkitViewer.traceScreenPoint(0));
  await page.mouse.click(at.x, at.y);
  await page.waitForTimeout(200);
  const info = await page.textContent('#info');
  check(await page.evaluate(() => document.body.dataset.selected === '0'), 'clicking the trace selects it');
  check(/fraction: 0\.\d+/.test(info) && /contact: (edge|trmvertex|modelvertex)/.test(info),
    `contact shown: ${info.replace(/\n/g, ' | ')}`);
  check(info.includes('entity: worldspawn'), 'the world result names the entity hit');
  await page.click('#traces li[data-trace="1"]');
  check((await page.textContent('#info')).includes('#1 translation'), 'the list selects a trace');

  // Entities: the door is listed with its class; clicking it shows it.
  const options = await page.$$eval('#entities option', (os) => os.map((o) => o.textContent));
  check(options.includes('door1 (func_door)'), `entities listed: ${options.join(', ')}`);
  const door = await page.evaluate(() => window.cmkitViewer.entityScreenPoint('door1'));
  await page.mouse.click(door.x, door.y);
  await page.waitForTimeout(200);
  const doorInfo = await page.textContent('#info');
  check(doorInfo.includes('entity door1') && doorInfo.includes('class: func_door'),
    `clicking the door shows it: ${doorInfo.replace(/\n/g, ' | ')}`);
  await page.selectOption('#entities', 'door1');
  check(await page.evaluate(() => document.body.dataset.entity === 'door1'), 'the list selects an entity');
  await page.uncheck('#show-entities');

  // Audit findings: listed and drawn; clicking the embedded start shows it and its path.
  const found = await page.evaluate(() => window.cmkitViewer.findings.map((f) => [f.number, f.kind]));
  const embedded = found.find(([, kind]) => kind === 'embedded');
  check(embedded !== undefined, `audit findings shown: ${JSON.stringify(found)}`);
  check((await page.textContent('#status')).includes('audit findings'), 'the status counts the findings');
  if (embedded) {
    const spot = await page.evaluate((n) => window.cmkitViewer.findingScreenPoint(n), embedded[0]);
    await page.mouse.click(spot.x, spot.y);
    await page.waitForTimeout(200);
    const findingInfo = await page.textContent('#info');
    check(findingInfo.includes(`finding ${embedded[0]}: embedded, high`) && findingInfo.includes('start_in_pillar'),
      `clicking a finding shows it: ${findingInfo.replace(/\n/g, ' | ')}`);
  }

  // Toggles: internal edges on, a contents kind off.
  await page.check('#show-internal');
  const kinds = await page.$$('#contents input');
  check(kinds.length >= 2, `${kinds.length} contents kinds listed`);
  if (kinds.length) await kinds[0].uncheck();
  check(errors.length === 0, `no page errors ${errors.join('; ')}`);
} catch (err) {
  console.error(err);
  failed = true;
} finally {
  await browser?.close();
  server?.kill();
  rmSync(work, { recursive: true, force: true });
}
console.log(failed ? 'viewer test FAILED' : 'viewer test passed');
process.exit(failed ? 1 : 0);
