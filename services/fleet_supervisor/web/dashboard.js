// fleetloc dashboard: live fleet state from the supervisor's event stream (/api/events), the
// mosaic overview from /api/tiles, history plots from /api/vehicles/ID/history, re-mapping with
// the maintainer token. Map frame per docs/formats.md: x right, y up, theta counter-clockwise.
'use strict';

const LOCK_COLOURS = { tracking: '#2ecc71', relocalized: '#1abc9c', coasting: '#f39c12', lost: '#e74c3c' };
const SILENT_COLOUR = '#7f8c8d';
const TRAIL_PERIOD_S = 0.25, TRAIL_LENGTH_S = 10;

const state = {
  snapshot: null, snapshots: 0, lastSnapshotAt: 0,
  trails: new Map(),          // id -> [[t, x, y], ...]
  mosaic: null,               // /api/mosaic
  view: null,                 // {cx, cy, scale} (scale: screen px per metre)
  selected: null, token: sessionStorage.getItem('fleetloc-token') || '', maintainer: false,
  selecting: false, region: null, drag: null,
};
window.fleetDashboard = state;  // for tests and the curious

const $ = (id) => document.getElementById(id);
const canvas = $('map'), ctx = canvas.getContext('2d');
const tileImages = new Map();

function esc(text) {
  return String(text).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' }[c]));
}
function ago(t) { const s = Date.now() / 1000 - t; return s < 1 ? 'now' : s < 120 ? `${s.toFixed(0)} s` : `${(s / 60).toFixed(0)} min`; }
function lockOf(v) { return v.pose ? v.pose.lock : 'unknown'; }
function colourOf(v) { return v.silent ? SILENT_COLOUR : LOCK_COLOURS[lockOf(v)] || SILENT_COLOUR; }

// ---- map view -------------------------------------------------------------------------------
function toScreen(x, y) {
  const v = state.view;
  return [(x - v.cx) * v.scale + canvas.width / 2, canvas.height / 2 - (y - v.cy) * v.scale];
}
function toMap(sx, sy) {
  const v = state.view;
  return [(sx - canvas.width / 2) / v.scale + v.cx, v.cy - (sy - canvas.height / 2) / v.scale];
}
// Shows the whole mosaic and every vehicle (base_link may lie off the floor it sees: the camera
// is mounted ahead of it). Refitted until the operator pans or zooms.
function fitView() {
  const m = state.mosaic, box = [Infinity, Infinity, -Infinity, -Infinity];
  const grow = (x, y) => { box[0] = Math.min(box[0], x); box[1] = Math.min(box[1], y); box[2] = Math.max(box[2], x); box[3] = Math.max(box[3], y); };
  if (m) { grow(m.origin_x, m.origin_y); grow(m.origin_x + m.width_px * m.resolution, m.origin_y - m.height_px * m.resolution); }
  if (state.snapshot) state.snapshot.vehicles.forEach((v) => v.pose && grow(v.pose.x, v.pose.y));
  if (!(box[2] > box[0])) { state.view = { cx: 0, cy: 0, scale: 100 }; return; }
  const w = Math.max(box[2] - box[0], 0.1), h = Math.max(box[3] - box[1], 0.1);
  state.view = { cx: (box[0] + box[2]) / 2, cy: (box[1] + box[3]) / 2,
                 scale: 0.9 * Math.min(canvas.width / w, canvas.height / h) };
}
function resize() {
  const r = canvas.getBoundingClientRect();
  canvas.width = Math.max(100, r.width); canvas.height = Math.max(100, r.height);
  if (!state.view) fitView();
  draw();
}

function drawTiles() {
  const m = state.mosaic;
  if (!m) return;
  const ideal = Math.round(Math.log2(1 / (state.view.scale * m.resolution)));
  const level = Math.max(m.min_level, Math.min(m.levels - 1, ideal));
  const tileM = m.tile_size_px * m.resolution * 2 ** level;
  const [x0, y1] = toMap(0, 0), [x1, y0] = toMap(canvas.width, canvas.height);
  const cols = Math.ceil(m.width_px / (m.tile_size_px * 2 ** level)), rows = Math.ceil(m.height_px / (m.tile_size_px * 2 ** level));
  const c0 = Math.max(0, Math.floor((x0 - m.origin_x) / tileM)), c1 = Math.min(cols - 1, Math.floor((x1 - m.origin_x) / tileM));
  const r0 = Math.max(0, Math.floor((m.origin_y - y1) / tileM)), r1 = Math.min(rows - 1, Math.floor((m.origin_y - y0) / tileM));
  ctx.imageSmoothingEnabled = true;
  for (let r = r0; r <= r1; r++) {
    for (let c = c0; c <= c1; c++) {
      const url = `/api/tiles/${level}/${c}/${r}.png?v=${m.version}`;
      let img = tileImages.get(url);
      if (!img) {
        img = new Image();
        img.onload = draw;
        img.src = url;
        tileImages.set(url, img);
      }
      if (!img.complete || !img.naturalWidth) continue;
      const [sx, sy] = toScreen(m.origin_x + c * tileM, m.origin_y - r * tileM);
      const size = tileM * state.view.scale;
      ctx.drawImage(img, sx, sy, size + 0.5, size + 0.5);
    }
  }
}

// The 3-sigma ellipse of a position covariance [xx, xy, yy] (principal axes by eigen-decomposition).
function drawEllipse(x, y, cov, colour) {
  const [a, b, d] = cov, tr = (a + d) / 2, det = Math.sqrt(Math.max(0, ((a - d) / 2) ** 2 + b * b));
  const l1 = tr + det, l2 = Math.max(0, tr - det), angle = Math.atan2(l1 - a, b || 1e-30);
  const [sx, sy] = toScreen(x, y);
  const r1 = 3 * Math.sqrt(l1) * state.view.scale, r2 = 3 * Math.sqrt(l2) * state.view.scale;
  if (r1 < 1) return;
  ctx.beginPath();
  ctx.ellipse(sx, sy, r1, Math.max(r2, 0.5), -(b === 0 && a >= d ? 0 : angle), 0, 2 * Math.PI);
  ctx.strokeStyle = colour; ctx.lineWidth = 1.5; ctx.setLineDash([4, 3]); ctx.stroke(); ctx.setLineDash([]);
}

function drawVehicle(v) {
  if (!v.pose) return;
  const colour = colourOf(v), p = v.pose;
  const trail = state.trails.get(v.id) || [];
  if (trail.length > 1) {
    ctx.beginPath();
    trail.forEach(([, x, y], i) => { const [sx, sy] = toScreen(x, y); i ? ctx.lineTo(sx, sy) : ctx.moveTo(sx, sy); });
    ctx.strokeStyle = colour + '88'; ctx.lineWidth = 1.5; ctx.stroke();
  }
  drawEllipse(p.x, p.y, [p.cov[0], p.cov[1], p.cov[2]], colour);
  const [sx, sy] = toScreen(p.x, p.y), size = 11;
  ctx.save(); ctx.translate(sx, sy); ctx.rotate(-p.theta);
  ctx.beginPath(); ctx.moveTo(size * 1.4, 0); ctx.lineTo(-size, size * 0.8); ctx.lineTo(-size * 0.5, 0); ctx.lineTo(-size, -size * 0.8); ctx.closePath();
  ctx.fillStyle = colour; ctx.fill();
  ctx.lineWidth = state.selected === v.id ? 3 : 1; ctx.strokeStyle = state.selected === v.id ? '#fff' : '#000'; ctx.stroke();
  ctx.restore();
  ctx.font = 'bold 13px system-ui'; ctx.fillStyle = '#fff'; ctx.strokeStyle = '#000'; ctx.lineWidth = 3;
  ctx.strokeText(v.id, sx + 12, sy - 12); ctx.fillText(v.id, sx + 12, sy - 12);
}

function drawRegion() {
  if (!state.region) return;
  const [x0, y0, x1, y1] = state.region, [ax, ay] = toScreen(x0, y1), [bx, by] = toScreen(x1, y0);
  ctx.fillStyle = 'rgba(45, 93, 155, 0.25)'; ctx.fillRect(ax, ay, bx - ax, by - ay);
  ctx.strokeStyle = '#5dade2'; ctx.lineWidth = 2; ctx.strokeRect(ax, ay, bx - ax, by - ay);
}

function draw() {
  if (!state.view) return;
  ctx.fillStyle = '#000'; ctx.fillRect(0, 0, canvas.width, canvas.height);
  drawTiles();
  drawRegion();
  if (state.snapshot) state.snapshot.vehicles.forEach(drawVehicle);
}

canvas.addEventListener('mousedown', (e) => {
  const [x, y] = toMap(e.offsetX, e.offsetY);
  state.userView = true;
  state.drag = { sx: e.offsetX, sy: e.offsetY, x, y, view: { ...state.view } };
});
canvas.addEventListener('mousemove', (e) => {
  const [x, y] = toMap(e.offsetX, e.offsetY);
  $('cursor').textContent = `x ${x.toFixed(3)} m, y ${y.toFixed(3)} m`;
  if (!state.drag) return;
  if (state.selecting) {
    state.region = [Math.min(state.drag.x, x), Math.min(state.drag.y, y), Math.max(state.drag.x, x), Math.max(state.drag.y, y)];
    showRegion();
  } else {
    state.view.cx = state.drag.view.cx - (e.offsetX - state.drag.sx) / state.view.scale;
    state.view.cy = state.drag.view.cy + (e.offsetY - state.drag.sy) / state.view.scale;
  }
  draw();
});
window.addEventListener('mouseup', () => { state.drag = null; });
canvas.addEventListener('wheel', (e) => {
  e.preventDefault();
  state.userView = true;
  const [x, y] = toMap(e.offsetX, e.offsetY), f = Math.exp(-e.deltaY * 0.0015);
  state.view.scale *= f;
  state.view.cx = x - (x - state.view.cx) / f; state.view.cy = y - (y - state.view.cy) / f;
  draw();
}, { passive: false });
canvas.addEventListener('click', (e) => {
  if (state.selecting || !state.snapshot) return;
  let best = null, bestD = 20;
  for (const v of state.snapshot.vehicles) {
    if (!v.pose) continue;
    const [sx, sy] = toScreen(v.pose.x, v.pose.y), d = Math.hypot(sx - e.offsetX, sy - e.offsetY);
    if (d < bestD) { best = v.id; bestD = d; }
  }
  if (best) select(best);
});

// ---- live state -----------------------------------------------------------------------------
function addTrailPoint(v) {
  if (!v.pose) return;
  let trail = state.trails.get(v.id);
  if (!trail) state.trails.set(v.id, (trail = []));
  const last = trail[trail.length - 1];
  if (last && v.pose.t < last[0] + TRAIL_PERIOD_S) return;
  trail.push([v.pose.t, v.pose.x, v.pose.y]);
  while (trail.length && trail[0][0] < v.pose.t - TRAIL_LENGTH_S) trail.shift();
}

function renderSummary(s) {
  const part = (label, n, cls) => `<span class="${cls || ''}"><b>${n}</b> ${label}</span>`;
  $('summary').innerHTML = part('vehicles', s.vehicles) + part('tracking', s.tracking, 'lock-tracking') +
    part('coasting', s.coasting, 'lock-coasting') + part('lost', s.lost, 'lock-lost') +
    part('silent', s.silent) + part('critical', s.critical_alerts, 'lock-lost') + part('warnings', s.warning_alerts, 'level-warn');
}

function renderVehicles(vehicles) {
  $('vehicles').tBodies[0].innerHTML = vehicles.map((v) => {
    const h = v.health || {}, p = v.pose || {};
    const lock = v.silent ? 'silent' : lockOf(v);
    return `<tr data-vehicle="${esc(v.id)}" data-lock="${esc(lock)}" class="${v.silent ? 'silent-row' : ''} ${state.selected === v.id ? 'selected' : ''}">
      <td>${esc(v.id)}</td><td class="lock-${esc(lockOf(v))}">${esc(v.silent ? 'STALE' : lock)}</td>
      <td class="level-${esc(h.level || '')}">${esc(h.level || '–')}</td>
      <td>${p.deviation_m !== undefined ? (p.deviation_m * 1e3 / 3).toFixed(2) : '–'}</td>
      <td>${h.inliers ?? '–'}</td><td>${h.cycle_ms ? h.cycle_ms[1].toFixed(1) + ' ms' : '–'}</td>
      <td>${ago(v.last_seen)}</td><td class="issues">${esc((h.issues || []).join(', '))}</td></tr>`;
  }).join('');
}

function renderAlerts(alerts) {
  $('alert-count').textContent = alerts.length ? `(${alerts.length} active)` : '';
  $('alerts').innerHTML = alerts.length ? alerts.map((a) =>
    `<li class="${esc(a.severity)}" data-vehicle="${esc(a.vehicle)}" data-kind="${esc(a.kind)}">
       <b>${esc(a.vehicle)}</b> ${esc(a.kind.replace(/_/g, ' '))} — ${esc(a.message)} <span class="info">since ${ago(a.raised)}</span></li>`).join('')
    : '<li class="none">no active alerts</li>';
}

function renderJobs(jobs) {
  jobs.sort((a, b) => b.t - a.t);
  $('jobs').innerHTML = jobs.map((j) =>
    `<li data-command="${esc(j.command_id)}" data-server="${esc(j.server_id)}" data-state="${esc(j.state)}">
       <span class="state-${esc(j.state)}">${esc(j.state.toUpperCase())}</span> job …${esc(j.command_id.slice(-6))} on ${esc(j.server_id)}
       ${j.state === 'running' || j.state === 'queued' ? `<progress max="1" value="${j.progress}"></progress> ${esc(j.phase)}` : ''}
       ${j.state === 'done' ? `version ${j.new_version}, ${j.tiles_changed} tiles, ${j.patches_folded} patches` : ''}
       ${j.message ? `<div class="info">${esc(j.message)}</div>` : ''}</li>`).join('');
}

function renderStatus(s) {
  const alive = s.map_server_alive;
  $('mapsrv').className = `pill ${alive ? 'ok' : 'bad'}`;
  $('mapsrv').textContent = alive ? 'map server up' : 'map server unreachable';
  $('mosaic').textContent = s.mosaic ? `mosaic ${s.mosaic.mosaic_id} v${s.mosaic.version}` : 'no mosaic';
  if (s.mosaic && (!state.mosaic || state.mosaic.version !== s.mosaic.version)) loadMosaic();
}

function onSnapshot(snapshot) {
  state.snapshot = snapshot; state.snapshots++; state.lastSnapshotAt = Date.now();
  snapshot.vehicles.forEach(addTrailPoint);
  renderSummary(snapshot.summary); renderVehicles(snapshot.vehicles); renderAlerts(snapshot.alerts);
  renderJobs(snapshot.remap_jobs); renderStatus(snapshot);
  if (state.selected) renderDetailInfo();
  const outside = (v) => { if (!v.pose) return false; const [sx, sy] = toScreen(v.pose.x, v.pose.y); return sx < 0 || sy < 0 || sx > canvas.width || sy > canvas.height; };
  if (!state.userView && snapshot.vehicles.some(outside)) fitView();
  draw();
}

function connect() {
  const events = new EventSource('/api/events');
  events.onopen = () => { $('conn').className = 'pill ok'; $('conn').textContent = 'live'; };
  events.onerror = () => { $('conn').className = 'pill bad'; $('conn').textContent = 'reconnecting'; };
  events.onmessage = (e) => onSnapshot(JSON.parse(e.data));
}

async function loadMosaic() {
  const res = await fetch('/api/mosaic');
  if (!res.ok) { setTimeout(loadMosaic, 2000); return; }
  state.mosaic = await res.json();
  if (!state.userView) fitView();
  draw();
}

async function loadTrails() {
  const res = await fetch('/api/fleet?trails=1');
  if (!res.ok) return;
  for (const v of (await res.json()).vehicles) if (v.trail) state.trails.set(v.id, v.trail);
}

// ---- vehicle detail ---------------------------------------------------------------------------
function select(id) {
  state.selected = id;
  $('detail').hidden = false; $('detail-id').textContent = id;
  renderDetailInfo(); loadHistory(); draw();
}
$('detail-close').onclick = () => { state.selected = null; $('detail').hidden = true; draw(); };
$('vehicles').addEventListener('click', (e) => { const tr = e.target.closest('tr[data-vehicle]'); if (tr) select(tr.dataset.vehicle); });

function renderDetailInfo() {
  const v = state.snapshot && state.snapshot.vehicles.find((x) => x.id === state.selected);
  if (!v) return;
  const p = v.pose, h = v.health;
  $('detail-info').innerHTML = (p ? `pose x ${p.x.toFixed(4)} m, y ${p.y.toFixed(4)} m, θ ${(p.theta * 180 / Math.PI).toFixed(2)}°, ` +
    `score ${p.score.toFixed(2)}, mosaic v${p.mosaic_version}` : 'no pose') +
    (h ? `<br>cache hit ${(h.cache_hit_rate * 100).toFixed(0)} %, tiles pending ${h.tiles_pending}, outbox ${h.patch_outbox}, ` +
    `frame drops ${h.camera_frame_drops}${h.last_error ? `, last error: ${esc(h.last_error)}` : ''}` : '');
}

function plot(id, t, values, colour) {
  const c = $(id), g = c.getContext('2d');
  c.width = c.clientWidth; c.height = c.clientHeight;
  g.fillStyle = '#161a20'; g.fillRect(0, 0, c.width, c.height);
  if (t.length < 2) { g.fillStyle = '#777'; g.fillText('no data yet', 8, 16); return; }
  const t0 = t[0], t1 = t[t.length - 1], lo = Math.min(0, ...values), hi = Math.max(...values, lo + 1e-9);
  const px = (x) => ((x - t0) / Math.max(t1 - t0, 1e-9)) * (c.width - 40) + 36;
  const py = (y) => c.height - 6 - ((y - lo) / (hi - lo)) * (c.height - 14);
  g.fillStyle = '#999'; g.font = '11px system-ui';
  g.fillText(hi.toPrecision(3), 2, 12); g.fillText(lo.toPrecision(3), 2, c.height - 4);
  g.beginPath(); t.forEach((x, i) => (i ? g.lineTo(px(x), py(values[i])) : g.moveTo(px(x), py(values[i]))));
  g.strokeStyle = colour; g.lineWidth = 1.5; g.stroke();
}

async function loadHistory() {
  const id = state.selected;
  if (!id) return;
  const to = Date.now() / 1000;
  const res = await fetch(`/api/vehicles/${encodeURIComponent(id)}/history?from=${to - 600}&to=${to}&max_points=400`);
  if (!res.ok || id !== state.selected) return;
  const h = await res.json();
  plot('plot-deviation', h.poses.t, h.poses.deviation_m.map((d) => d * 1e3), '#5dade2');
  plot('plot-inliers', h.health.t, h.health.inliers, '#2ecc71');
  plot('plot-cycle', h.health.t, h.health.cycle_ms_p95, '#f39c12');
}
setInterval(loadHistory, 5000);

// ---- maintainer mode and re-mapping -----------------------------------------------------------
function setMaintainer(on) {
  state.maintainer = on;
  $('mode').className = `pill ${on ? 'warn' : ''}`; $('mode').textContent = on ? 'maintainer' : 'read-only';
  for (const id of ['select-region', 'remap-mode', 'start-remap']) $(id).disabled = !on;
}

async function unlock(token) {
  const res = await fetch('/api/auth', { headers: { Authorization: `Bearer ${token}` } });
  if (res.ok) { state.token = token; sessionStorage.setItem('fleetloc-token', token); setMaintainer(true); $('remap-error').textContent = ''; return; }
  setMaintainer(false); sessionStorage.removeItem('fleetloc-token');
  $('remap-error').textContent = (await res.json()).error;
}
$('auth').addEventListener('submit', (e) => { e.preventDefault(); unlock($('token').value); });

function showRegion() {
  const r = state.region;
  $('region').textContent = r ? `region x ${r[0].toFixed(3)} … ${r[2].toFixed(3)} m, y ${r[1].toFixed(3)} … ${r[3].toFixed(3)} m` : 'no region selected';
}
$('select-region').onclick = () => {
  state.selecting = !state.selecting;
  $('select-region').classList.toggle('active', state.selecting);
  canvas.classList.toggle('selecting', state.selecting);
};

async function startRemap() {
  $('remap-error').textContent = '';
  if (!state.region) { $('remap-error').textContent = 'select a region on the map first'; return; }
  const res = await fetch('/api/remap', {
    method: 'POST', headers: { 'Content-Type': 'application/json', Authorization: `Bearer ${state.token}` },
    body: JSON.stringify({ region: state.region, mode: $('remap-mode').value }),
  });
  const body = await res.json();
  if (!res.ok) { $('remap-error').textContent = body.error; return; }
  $('region').textContent = `job …${body.command_id.slice(-6)} started`;
  state.selecting = false; $('select-region').classList.remove('active'); canvas.classList.remove('selecting');
}
$('start-remap').onclick = startRemap;

window.addEventListener('resize', resize);
setInterval(() => { if (state.snapshot) renderVehicles(state.snapshot.vehicles); }, 1000);
resize();
loadMosaic();
loadTrails().then(connect);
if (state.token) unlock(state.token);
