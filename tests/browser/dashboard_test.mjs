// Drives the fleet supervisor's dashboard in headless Debian chromium (playwright-core): vehicles
// appear and move; killing an agent raises an alert on the page; the page is read-only without
// the maintainer token (and the API refuses a re-map: 401 / 403); with it, a re-mapping job
// started from the page (region dragged on the map) completes and the page shows DONE.
// The map (Leaflet, issue 22): mosaic tiles, a metric scale bar that agrees with the zoom, a metric
// grid, the mosaic's name and version (not its id), uncertainty ellipses visible from the coarsest
// to the finest zoom, "follow vehicle", plots with clock-time axes, and a map that keeps most of the
// width at 1024 px. Screenshots go to --out. Run by tests/dashboard_browser_test.cpp; exits non-zero
// on failure.
//   node dashboard_test.mjs --url URL --token TOKEN --kill-pid PID --kill-vehicle ID --out DIR
//        --mosaic-name NAME
import { createRequire } from 'node:module';
import { mkdirSync } from 'node:fs';
import { parseArgs } from 'node:util';

const { values: args } = parseArgs({
  options: {
    url: { type: 'string' }, token: { type: 'string' }, 'kill-pid': { type: 'string' },
    'kill-vehicle': { type: 'string' }, out: { type: 'string' }, 'mosaic-name': { type: 'string' },
    chromium: { type: 'string', default: '/usr/bin/chromium' },
  },
});
const require = createRequire(`${process.env.FLEETLOC_NODE_MODULES}/`);
const { chromium } = require('playwright-core');

const step = (text) => console.log(`[dashboard] ${text}`);
function check(condition, message) { if (!condition) throw new Error(message); }

// Parses a length label of the scale bar or grid ("50 cm", "2 m", "5 mm") into metres.
function metresOf(label) {
  const m = /^(-?[0-9.]+) (mm|cm|m|km)$/.exec(label.trim());
  check(m, `not a metric length: '${label}'`);
  return Number(m[1]) * { mm: 1e-3, cm: 1e-2, m: 1, km: 1e3 }[m[2]];
}

async function checkMap(page, ids) {
  step('Leaflet map: scale bar, grid, mosaic name');
  const mpp = await page.evaluate(() => window.fleetDashboard.mapView.metresPerPixel());
  const scale = await page.$eval('.leaflet-control-scale-line', (e) => ({ text: e.textContent, width: e.getBoundingClientRect().width }));
  const scaleM = metresOf(scale.text);
  step(`scale bar ${scale.text} over ${scale.width.toFixed(0)} px at ${(mpp * 1000).toFixed(3)} mm/px`);
  check(Math.abs(scale.width * mpp - scaleM) / scaleM < 0.05, `the scale bar says ${scale.text} but spans ${(scale.width * mpp).toFixed(4)} m`);
  const grid = await page.$$eval('.grid-label', (ls) => ls.map((l) => l.textContent));
  check(await page.$$eval('.grid-line', (ls) => ls.length) >= 4, 'fewer than 4 grid lines');
  const xs = grid.slice(0, 2).map(metresOf);
  const step_m = await page.evaluate(() => window.fleetDashboard.mapView.gridStep);
  check(Math.abs(Math.abs(xs[1] - xs[0]) - step_m) < 1e-9, `grid labels ${grid.slice(0, 2)} are not ${step_m} m apart`);
  const mosaic = (await page.textContent('#mosaic')).trim();
  step(`mosaic shown as '${mosaic}'`);
  check(mosaic.startsWith(args['mosaic-name']) && /version \d+/.test(mosaic), `mosaic pill '${mosaic}' lacks the name or version`);
  check(!/[0-9a-f]{16}/.test(mosaic), `mosaic pill shows a hash: '${mosaic}'`);
  await page.screenshot({ path: `${args.out}/05_map_checks.png` });

  step('uncertainty ellipses at every zoom');
  const zooms = await page.evaluate(() => { const m = window.fleetDashboard.mapView.map; return [m.getMinZoom(), m.getMaxZoom()]; });
  for (let zoom = zooms[0]; zoom <= zooms[1]; zoom += 3) {
    const z = Math.min(zoom, zooms[1]);
    // Centred on the vehicle and measured at once: at the finest zoom it crosses the screen in
    // a fraction of a second.
    const box = await page.evaluate(([z, id]) => {
      const v = window.fleetDashboard.mapView, p = v.vehicles.get(id).pose;
      v.map.setView([p.y, p.x], z, { animate: false });
      v.redrawEllipses();
      const r = document.querySelector(`path.ellipse[data-vehicle="${id}"]`).getBoundingClientRect();
      return [r.width, r.height];
    }, [z, ids[0]]);
    check(Math.min(...box) >= 10, `the ellipse of ${ids[0]} is ${box[0].toFixed(1)}x${box[1].toFixed(1)} px at zoom ${z}`);
    step(`zoom ${z}: ellipse ${box[0].toFixed(0)}x${box[1].toFixed(0)} px`);
    if (z === zooms[1]) {
      await page.evaluate((id) => window.fleetDashboard.mapView.setFollow(id), ids[0]);  // for the picture
      await page.waitForTimeout(300);
      await page.screenshot({ path: `${args.out}/06_ellipse_zoom_max.png` });
      await page.evaluate(() => window.fleetDashboard.mapView.setFollow(null));
    }
  }
  await page.evaluate(() => window.fleetDashboard.mapView.fit());
}

async function checkFollow(page, id) {
  step(`follow ${id}`);
  await page.check('#follow');
  const offsets = [];
  for (let i = 0; i < 3; i++) {
    await page.waitForTimeout(700);
    offsets.push(await page.evaluate((id) => { const v = window.fleetDashboard.mapView; const p = v.vehicles.get(id).pose;
      const c = v.map.latLngToContainerPoint([p.y, p.x]), s = v.map.getSize(); return Math.hypot(c.x - s.x / 2, c.y - s.y / 2); }, id));
  }
  step(`vehicle ${offsets.map((o) => o.toFixed(0)).join(', ')} px from the map centre`);
  check(offsets.every((o) => o < 40), `the map does not follow ${id}: ${offsets}`);
  await page.screenshot({ path: `${args.out}/07_follow.png` });
  await page.uncheck('#follow');
}

async function checkPlots(page) {
  step('plots with time axes');
  await page.waitForFunction(() => window.fleetDashboard.plots.charts.deviation.data.datasets[0].data.length > 1, null, { timeout: 15000 });
  for (const name of ['deviation', 'inliers', 'cycle']) {
    const axis = await page.evaluate((n) => { const c = window.fleetDashboard.plots.charts[n];
      return { title: c.options.scales.x.title.text, labels: c.scales.x.ticks.map((t) => t.label), y: c.options.scales.y.title.text }; }, name);
    check(axis.title === 'time' && axis.labels.length >= 2 && axis.labels.every((l) => /^\d\d:\d\d:\d\d$/.test(l)),
          `${name}: the x axis is not a clock-time axis: ${JSON.stringify(axis)}`);
    check(axis.y.length > 0, `${name}: no y axis title`);
  }
  await page.screenshot({ path: `${args.out}/08_plots.png` });
}

async function checkNarrowLayout(page) {
  step('layout at 1024 px');
  await page.setViewportSize({ width: 1024, height: 768 });
  await page.waitForTimeout(500);
  const width = await page.$eval('#map', (e) => e.getBoundingClientRect().width);
  step(`map ${width.toFixed(0)} of 1024 px`);
  check(width >= 0.6 * 1024, `at 1024 px the map gets only ${width} px`);
  await page.screenshot({ path: `${args.out}/09_1024px.png` });
}

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
  await page.waitForFunction(() => window.fleetDashboard.mosaic);
  await page.waitForFunction(() => [...document.querySelectorAll('img.mosaic-tile')].some((i) => i.complete && i.naturalWidth > 0),
                             null, { timeout: 20000 });
  await page.waitForTimeout(500);
  await page.screenshot({ path: `${args.out}/01_fleet.png` });
  await checkMap(page, ids);

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
  const alive = ids.find((id) => id !== args['kill-vehicle']);
  await page.click(`#vehicles tr[data-vehicle="${alive}"]`);
  await page.waitForTimeout(1500);
  await page.screenshot({ path: `${args.out}/04_detail.png` });
  await checkFollow(page, alive);
  await checkPlots(page);
  await checkNarrowLayout(page);
  check(errors.length === 0, `errors on the page: ${errors.join('; ')}`);
  step('passed');
} finally {
  await browser.close();
}
