// fleetloc dashboard map on Leaflet (Debian's libjs-leaflet, served at /vendor/leaflet/): a simple
// CRS in map metres (lat = y up, lng = x right, as in docs/formats.md), the mosaic's own tile
// pyramid as image overlays, a metric scale bar and grid, vehicles with their 3-sigma ellipses
// (never drawn smaller than a few pixels, so they stay visible at every zoom), trails, region
// selection for re-mapping and "follow vehicle".
'use strict';

const MIN_ELLIPSE_PX = 6;   // a 3-sigma ellipse smaller than this on screen is drawn at this size
const GRID_TARGET_PX = 90;  // grid spacing aimed at, on screen

// 1, 2 or 5 × 10^n: the largest such value not above `x`.
function roundStep(x) {
  const p = 10 ** Math.floor(Math.log10(x)), d = x / p;
  return (d >= 5 ? 5 : d >= 2 ? 2 : 1) * p;
}
function formatMetres(m) {
  const a = Math.abs(m);
  if (a >= 1000) return `${+(m / 1000).toPrecision(6)} km`;
  if (a >= 1 || a === 0) return `${+m.toPrecision(6)} m`;
  if (a >= 0.01) return `${+(m * 100).toPrecision(6)} cm`;
  return `${+(m * 1000).toPrecision(6)} mm`;
}

// Leaflet's scale bar rounds anything under a metre to "1 m"; floors are read in centimetres.
const MetricScale = L.Control.Scale.extend({
  _updateMetric(maxMeters) {
    const metres = roundStep(maxMeters);
    this._updateScale(this._mScale, formatMetres(metres), metres / maxMeters);
  },
});

class MapView {
  constructor(element, handlers) {
    this.handlers = handlers;  // {onVehicleClick(id), onRegion([x0,y0,x1,y1]), onCursor(x, y)}
    this.map = L.map(element, { crs: L.CRS.Simple, minZoom: -4, maxZoom: 14, zoomSnap: 0.25,
                                attributionControl: false, zoomControl: true });
    this.map.setView([0, 0], 6);
    this.scale = new MetricScale({ imperial: false, maxWidth: 160, position: 'bottomright' }).addTo(this.map);
    this.tiles = L.layerGroup().addTo(this.map);
    this.grid = L.layerGroup().addTo(this.map);
    this.overlay = L.layerGroup().addTo(this.map);
    this.vehicles = new Map();  // id -> {marker, ellipse, trail}
    this.tileOverlays = new Map();
    this.mosaic = null; this.mosaicFitted = false; this.userMoved = false; this.follow = null;
    this.selecting = false; this.region = null; this.regionLayer = null;
    this.map.on('moveend zoomend', () => { this.drawTiles(); this.drawGrid(); this.redrawEllipses(); });
    this.map.on('dragstart zoomstart', (e) => { if (!this.programmatic) this.userMoved = true; });
    this.map.on('mousemove', (e) => handlers.onCursor(e.latlng.lng, e.latlng.lat));
    this.installRegionSelection();
  }

  // Metres per screen pixel at the current zoom (CRS.Simple: 2^zoom pixels per metre).
  metresPerPixel() { return 1 / 2 ** this.map.getZoom(); }

  setMosaic(mosaic) {
    const changed = !this.mosaic || this.mosaic.version !== mosaic.version || this.mosaic.mosaic_id !== mosaic.mosaic_id;
    this.mosaic = mosaic;
    if (changed) { this.tiles.clearLayers(); this.tileOverlays.clear(); }
    if (!this.mosaicFitted && !this.userMoved) { this.fit(this.fitPoints || []); this.mosaicFitted = true; }
    this.drawTiles(); this.drawGrid();
  }

  bounds() {
    const m = this.mosaic;
    return L.latLngBounds([m.origin_y - m.height_px * m.resolution, m.origin_x], [m.origin_y, m.origin_x + m.width_px * m.resolution]);
  }

  // Shows the whole mosaic and `points` ([x, y] in metres: a vehicle's base_link may lie off the
  // floor its camera sees).
  fit(points = []) {
    this.fitPoints = points;
    let b = this.mosaic ? this.bounds() : null;
    for (const [x, y] of points) b = b ? b.extend([y, x]) : L.latLngBounds([y, x], [y, x]);
    if (!b) return;
    this.programmatic = true;
    this.map.fitBounds(b.pad(0.05), { animate: false });
    this.programmatic = false;
  }

  // The pyramid level whose pixels are closest to the screen's, and its visible tiles.
  drawTiles() {
    const m = this.mosaic;
    if (!m) return;
    const ideal = Math.round(Math.log2(this.metresPerPixel() / m.resolution));
    const level = Math.max(m.min_level, Math.min(m.levels - 1, ideal));
    const tileM = m.tile_size_px * m.resolution * 2 ** level;
    const view = this.map.getBounds();
    const cols = Math.ceil(m.width_px / (m.tile_size_px * 2 ** level)), rows = Math.ceil(m.height_px / (m.tile_size_px * 2 ** level));
    const c0 = Math.max(0, Math.floor((view.getWest() - m.origin_x) / tileM)), c1 = Math.min(cols - 1, Math.floor((view.getEast() - m.origin_x) / tileM));
    const r0 = Math.max(0, Math.floor((m.origin_y - view.getNorth()) / tileM)), r1 = Math.min(rows - 1, Math.floor((m.origin_y - view.getSouth()) / tileM));
    const wanted = new Set();
    for (let r = r0; r <= r1; r++) {
      for (let c = c0; c <= c1; c++) {
        const url = `/api/tiles/${level}/${c}/${r}.png?v=${m.version}`;
        wanted.add(url);
        if (this.tileOverlays.has(url)) continue;
        const x = m.origin_x + c * tileM, y = m.origin_y - r * tileM;
        const overlay = L.imageOverlay(url, [[y - tileM, x], [y, x + tileM]], { className: 'mosaic-tile' });
        this.tileOverlays.set(url, overlay.addTo(this.tiles));
      }
    }
    for (const [url, overlay] of this.tileOverlays) {
      if (!wanted.has(url)) { this.tiles.removeLayer(overlay); this.tileOverlays.delete(url); }
    }
  }

  // Grid lines every 1/2/5 × 10^n metres, about GRID_TARGET_PX apart, labelled at the left and top.
  drawGrid() {
    this.grid.clearLayers();
    const step = roundStep(GRID_TARGET_PX * this.metresPerPixel());
    const b = this.map.getBounds(), style = { className: 'grid-line', weight: 1, interactive: false };
    const label = (lat, lng, text, cls) => L.marker([lat, lng], { interactive: false, icon: L.divIcon({
      className: `grid-label ${cls}`, html: text, iconSize: null }) }).addTo(this.grid);
    const at = (i) => +(i * step).toPrecision(12);  // i × step without float noise ("0 m", not "1e-17 m")
    for (let i = Math.ceil(b.getWest() / step); at(i) <= b.getEast(); i++) {
      L.polyline([[b.getSouth(), at(i)], [b.getNorth(), at(i)]], style).addTo(this.grid);
      label(b.getNorth(), at(i), formatMetres(at(i)), 'grid-x');
    }
    for (let i = Math.ceil(b.getSouth() / step); at(i) <= b.getNorth(); i++) {
      L.polyline([[at(i), b.getWest()], [at(i), b.getEast()]], style).addTo(this.grid);
      label(at(i), b.getWest(), formatMetres(at(i)), 'grid-y');
    }
    this.gridStep = step;
  }

  // The 3-sigma ellipse of position covariance [xx, xy, yy] as a polygon in metres, grown to at
  // least MIN_ELLIPSE_PX on screen.
  ellipsePoints(x, y, cov) {
    const [a, b, d] = cov, tr = (a + d) / 2, det = Math.sqrt(Math.max(0, ((a - d) / 2) ** 2 + b * b));
    const l1 = tr + det, l2 = Math.max(0, tr - det);
    const angle = Math.abs(b) < 1e-30 ? (a >= d ? 0 : Math.PI / 2) : Math.atan2(l1 - a, b);
    const minM = MIN_ELLIPSE_PX * this.metresPerPixel();
    const r1 = Math.max(3 * Math.sqrt(l1), minM), r2 = Math.max(3 * Math.sqrt(l2), minM);
    const pts = [];
    for (let i = 0; i < 36; i++) {
      const t = (i / 36) * 2 * Math.PI, u = r1 * Math.cos(t), v = r2 * Math.sin(t);
      pts.push([y + u * Math.sin(angle) + v * Math.cos(angle), x + u * Math.cos(angle) - v * Math.sin(angle)]);
    }
    return pts;
  }

  arrowIcon(colour, theta, selected) {
    const deg = -theta * 180 / Math.PI;
    return L.divIcon({ className: 'vehicle-icon', iconSize: [28, 28], iconAnchor: [14, 14],
      html: `<svg width="28" height="28" viewBox="-14 -14 28 28" style="transform: rotate(${deg}deg)">
        <path d="M13 0 L-9 8 L-4 0 L-9 -8 Z" fill="${colour}" stroke="${selected ? '#fff' : '#000'}" stroke-width="${selected ? 2.5 : 1}"/></svg>` });
  }

  // Draws every vehicle of a snapshot (colourOf(v) gives its colour, trails its recent path).
  setVehicles(vehicles, colourOf, trails, selected) {
    const seen = new Set();
    for (const v of vehicles) {
      if (!v.pose) continue;
      seen.add(v.id);
      let item = this.vehicles.get(v.id);
      const colour = colourOf(v), p = v.pose, latlng = [p.y, p.x];
      if (!item) {
        item = {
          marker: L.marker(latlng, { title: v.id }).bindTooltip(v.id, { permanent: true, direction: 'right', offset: [10, -10], className: 'vehicle-label' }),
          ellipse: L.polygon([], { className: 'ellipse', weight: 1.5, dashArray: '4 3', fillOpacity: 0.08, interactive: false }),
          trail: L.polyline([], { weight: 1.5, opacity: 0.55, interactive: false }),
        };
        item.marker.on('click', () => this.handlers.onVehicleClick(v.id));
        item.trail.addTo(this.overlay); item.ellipse.addTo(this.overlay); item.marker.addTo(this.overlay);
        this.vehicles.set(v.id, item);
      }
      item.pose = p;
      item.marker.setLatLng(latlng).setIcon(this.arrowIcon(colour, p.theta, selected === v.id));
      item.marker.getElement()?.setAttribute('data-vehicle', v.id);
      item.ellipse.setStyle({ color: colour }).setLatLngs(this.ellipsePoints(p.x, p.y, p.cov));
      item.ellipse.getElement()?.setAttribute('data-vehicle', v.id);
      item.trail.setStyle({ color: colour }).setLatLngs((trails.get(v.id) || []).map(([, x, y]) => [y, x]));
    }
    for (const [id, item] of this.vehicles) {
      if (seen.has(id)) continue;
      this.overlay.removeLayer(item.marker); this.overlay.removeLayer(item.ellipse); this.overlay.removeLayer(item.trail);
      this.vehicles.delete(id);
    }
    this.followStep();
  }

  redrawEllipses() {
    for (const item of this.vehicles.values()) {
      if (item.pose) item.ellipse.setLatLngs(this.ellipsePoints(item.pose.x, item.pose.y, item.pose.cov));
    }
  }

  setFollow(id) { this.follow = id; this.followStep(); }
  followStep() {
    const item = this.follow && this.vehicles.get(this.follow);
    if (!item || !item.pose) return;
    this.programmatic = true;
    this.map.panTo([item.pose.y, item.pose.x], { animate: false });
    this.programmatic = false;
  }

  setSelecting(on) {
    this.selecting = on;
    this.map.getContainer().classList.toggle('selecting', on);
    on ? this.map.dragging.disable() : this.map.dragging.enable();
  }

  // While selecting, a drag draws the re-mapping region (map metres).
  installRegionSelection() {
    let start = null;
    this.map.on('mousedown', (e) => { if (this.selecting) start = e.latlng; });
    this.map.on('mousemove', (e) => {
      if (!this.selecting || !start) return;
      const a = start, b = e.latlng;
      this.region = [Math.min(a.lng, b.lng), Math.min(a.lat, b.lat), Math.max(a.lng, b.lng), Math.max(a.lat, b.lat)];
      const bounds = [[this.region[1], this.region[0]], [this.region[3], this.region[2]]];
      if (!this.regionLayer) this.regionLayer = L.rectangle(bounds, { className: 'region', weight: 2 }).addTo(this.overlay);
      this.regionLayer.setBounds(bounds);
      this.handlers.onRegion(this.region);
    });
    this.map.on('mouseup', () => { start = null; });
  }
}

window.MapView = MapView;
