// fleetloc dashboard: live fleet state from the supervisor's event stream (/api/events), the
// mosaic map (map_view.js) from /api/tiles, history plots (plots.js) from
// /api/vehicles/ID/history, re-mapping with the maintainer token. Map frame per docs/formats.md: x right, y up, theta counter-clockwise.
'use strict';

const LOCK_COLOURS = { tracking: '#2ecc71', relocalized: '#1abc9c', coasting: '#f39c12', lost: '#e74c3c' };
const SILENT_COLOUR = '#7f8c8d';
const TRAIL_PERIOD_S = 0.25, TRAIL_LENGTH_S = 10;

const state = {
  snapshot: null, snapshots: 0, lastSnapshotAt: 0,
  trails: new Map(),          // id -> [[t, x, y], ...]
  mosaic: null,               // /api/mosaic
  selected: null, token: sessionStorage.getItem('fleetloc-token') || '', maintainer: false,
  selecting: false, region: null, follow: null, mapView: null, plots: null,
};
window.fleetDashboard = state;  // for tests and the curious

const $ = (id) => document.getElementById(id);

function esc(text) {
  return String(text).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' }[c]));
}
function ago(t) { const s = Date.now() / 1000 - t; return s < 1 ? 'now' : s < 120 ? `${s.toFixed(0)} s` : `${(s / 60).toFixed(0)} min`; }
function lockOf(v) { return v.pose ? v.pose.lock : 'unknown'; }
function colourOf(v) { return v.silent ? SILENT_COLOUR : LOCK_COLOURS[lockOf(v)] || SILENT_COLOUR; }

// ---- map (map_view.js) ------------------------------------------------------------------------
const mapView = new MapView($('map'), {
  onVehicleClick: (id) => select(id),
  onRegion: (region) => { state.region = region; showRegion(); },
  onCursor: (x, y) => { $('cursor').textContent = `x ${x.toFixed(3)} m, y ${y.toFixed(3)} m`; },
});
state.mapView = mapView;
function draw() {
  if (state.snapshot) mapView.setVehicles(state.snapshot.vehicles, colourOf, state.trails, state.selected);
}
const plots = new VehiclePlots();
state.plots = plots;

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
  if (!s.mosaic) $('mosaic').textContent = 'no mosaic';
  if (s.mosaic && (!state.mosaic || state.mosaic.version !== s.mosaic.version)) loadMosaic();
}

function onSnapshot(snapshot) {
  state.snapshot = snapshot; state.snapshots++; state.lastSnapshotAt = Date.now();
  snapshot.vehicles.forEach(addTrailPoint);
  renderSummary(snapshot.summary); renderVehicles(snapshot.vehicles); renderAlerts(snapshot.alerts);
  renderJobs(snapshot.remap_jobs); renderStatus(snapshot);
  if (state.selected) renderDetailInfo();
  draw();
  if (!mapView.userMoved && !state.follow && !state.fittedVehicles && snapshot.vehicles.some((v) => v.pose)) {
    mapView.fit(snapshot.vehicles.filter((v) => v.pose).map((v) => [v.pose.x, v.pose.y]));
    state.fittedVehicles = true;
  }
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
  $('mosaic').textContent = `${state.mosaic.name} · version ${state.mosaic.version}`;
  $('mosaic').title = `mosaic id ${state.mosaic.mosaic_id}`;
  mapView.setMosaic(state.mosaic);
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
  $('follow').checked = state.follow === id;
  renderDetailInfo(); loadHistory(); draw();
}
$('detail-close').onclick = () => { state.selected = null; setFollow(null); $('detail').hidden = true; draw(); };
function setFollow(id) { state.follow = id; $('follow').checked = !!id; mapView.setFollow(id); }
$('follow').onchange = () => setFollow($('follow').checked ? state.selected : null);
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

async function loadHistory() {
  const id = state.selected;
  if (!id) return;
  const to = Date.now() / 1000;
  const res = await fetch(`/api/vehicles/${encodeURIComponent(id)}/history?from=${to - 600}&to=${to}&max_points=400`);
  if (!res.ok || id !== state.selected) return;
  plots.show(await res.json());
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
function setSelecting(on) {
  state.selecting = on;
  $('select-region').classList.toggle('active', on);
  mapView.setSelecting(on);
}
$('select-region').onclick = () => setSelecting(!state.selecting);

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
  setSelecting(false);
}
$('start-remap').onclick = startRemap;

setInterval(() => { if (state.snapshot) renderVehicles(state.snapshot.vehicles); }, 1000);
loadMosaic();
loadTrails().then(connect);
if (state.token) unlock(state.token);
