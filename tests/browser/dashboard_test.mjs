// Drives the fleet supervisor's dashboard in headless Debian chromium (playwright-core): vehicles
// appear and move; killing an agent raises an alert on the page; the page is read-only without
// the maintainer token (and the API refuses a re-map: 401 / 403); with it, a re-mapping job
// started from the page (region dragged on the map) completes and the page shows DONE.
// Screenshots go to --out. Run by tests/dashboard_browser_test.cpp; exits non-zero on failure.
//   node dashboard_test.mjs --url URL --token TOKEN --kill-pid PID --kill-vehicle ID --out DIR
import { createRequire } from 'node:module';
import { mkdirSync } from 'node:fs';
import { parseArgs } from 'node:util';

const { values: args } = parseArgs({
  options: {
    url: { type: 'string' }, token: { type: 'string' }, 'kill-pid': { type: 'string' },
    'kill-vehicle': { type: 'string' }, out: { type: 'string' },
    chromium: { type: 'string', default: '/usr/bin/chromium' },
  },
});
const require = createRequire(`${process.env.FLEETLOC_NODE_MODULES}/`);
const { chromium } = require('playwright-core');

const step = (text) => console.log(`[dashboard] ${text}`);
function check(condition, message) { if (!condition) throw new Error(message); }

mkdirSync(args.out, { recursive: true });
const browser = await chromium.launch({ executablePath: args.chromium, args: ['--no-sandbox'] });
try {
  const page = await browser.newPage({ viewport: { width: 1600, height: 900 } });
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(args.url);

  step('vehicles appear');
  await page.waitForFunction(() => {
    const s = window.fleetDashboard.snapshot;
    return s && s.vehicles.filter((v) => v.pose && !v.silent).length >= 2;
  }, null, { timeout: 60000 });
  await page.waitForSelector('#vehicles tbody tr[data-vehicle]');
  const ids = await page.$$eval('#vehicles tbody tr[data-vehicle]', (rows) => rows.map((r) => r.dataset.vehicle));
  check(ids.length >= 2, `expected two vehicles in the table, got ${ids}`);
  step(`vehicles in the table: ${ids.join(', ')}`);

  step('vehicles move');
  const poseOf = (id) => page.evaluate((i) => window.fleetDashboard.snapshot.vehicles.find((v) => v.id === i).pose, id);
  const before = await Promise.all(ids.map(poseOf));
  await page.waitForTimeout(2000);
  const after = await Promise.all(ids.map(poseOf));
  ids.forEach((id, i) => {
    const moved = Math.hypot(after[i].x - before[i].x, after[i].y - before[i].y);
    step(`${id} moved ${(moved * 1000).toFixed(1)} mm in 2 s`);
    check(moved > 0.001, `${id} did not move`);
  });
  await page.waitForFunction(() => document.querySelectorAll('img').length >= 0 && window.fleetDashboard.mosaic);
  await page.waitForTimeout(500);
  await page.screenshot({ path: `${args.out}/01_fleet.png` });

  step('read-only without the token');
  check(await page.isDisabled('#start-remap'), 'the re-map button is enabled without a token');
  const post = (headers) => page.evaluate(async (h) => (await fetch('/api/remap', {
    method: 'POST', headers: { 'Content-Type': 'application/json', ...h }, body: JSON.stringify({ region: [0, 0, 0.1, 0.1] }),
  })).status, headers);
  check(await post({}) === 401, 'POST /api/remap without a token is not 401');
  check(await post({ Authorization: 'Bearer wrong' }) === 403, 'POST /api/remap with a wrong token is not 403');

  step(`killing ${args['kill-vehicle']} (pid ${args['kill-pid']})`);
  process.kill(Number(args['kill-pid']), 'SIGKILL');
  const alert = `#alerts li[data-vehicle="${args['kill-vehicle']}"][data-kind="silent"]`;
  await page.waitForSelector(alert, { timeout: 30000 });
  step(`alert shown: ${(await page.textContent(alert)).trim().replace(/\s+/g, ' ')}`);
  await page.waitForSelector(`#vehicles tr[data-vehicle="${args['kill-vehicle']}"][data-lock="silent"]`);
  await page.screenshot({ path: `${args.out}/02_alert.png` });

  step('unlock with the maintainer token');
  await page.fill('#token', args.token);
  await page.click('#unlock');
  await page.waitForSelector('#start-remap:not([disabled])', { timeout: 10000 });

  step('select a region on the map and start a re-map');
  await page.click('#select-region');
  const box = await page.locator('#map').boundingBox();
  const cx = box.x + box.width / 2, cy = box.y + box.height / 2;
  await page.mouse.move(cx - 80, cy - 60);
  await page.mouse.down();
  await page.mouse.move(cx, cy, { steps: 5 });
  await page.mouse.move(cx + 80, cy + 60, { steps: 5 });
  await page.mouse.up();
  const region = await page.evaluate(() => window.fleetDashboard.region);
  check(region && region[2] > region[0] && region[3] > region[1], `no region selected: ${region}`);
  await page.click('#start-remap');
  await page.waitForSelector('#jobs li[data-state="done"]', { timeout: 90000 });
  step(`job shown: ${(await page.textContent('#jobs li[data-state="done"]')).trim().replace(/\s+/g, ' ')}`);
  await page.screenshot({ path: `${args.out}/03_remap_done.png` });

  step('vehicle detail with plots');
  await page.click(`#vehicles tr[data-vehicle="${ids.find((id) => id !== args['kill-vehicle'])}"]`);
  await page.waitForTimeout(1500);
  await page.screenshot({ path: `${args.out}/04_detail.png` });
  check(errors.length === 0, `errors on the page: ${errors.join('; ')}`);
  step('passed');
} finally {
  await browser.close();
}
