// fleetloc dashboard: a vehicle's history plots on Chart.js (Debian's libjs-chart.js, served at
// /vendor/chart.js/), each with a clock-time x axis and a labelled y axis.
'use strict';

const PLOT_STYLE = { grid: '#2c333d', text: '#b8b8b8' };

function clockLabel(t) {
  return new Date(t * 1000).toLocaleTimeString([], { hour12: false, hour: '2-digit', minute: '2-digit', second: '2-digit' });
}

// One time-series chart on `canvas`; `yTitle` names the quantity with its unit.
function makeTimePlot(canvas, yTitle, colour) {
  return new Chart(canvas, {
    type: 'line',
    data: { datasets: [{ data: [], borderColor: colour, backgroundColor: colour, borderWidth: 1.5, pointRadius: 0 }] },
    options: {
      animation: false, responsive: true, maintainAspectRatio: false, parsing: false, normalized: true,
      plugins: { legend: { display: false }, tooltip: { callbacks: { title: (items) => clockLabel(items[0].parsed.x) } } },
      scales: {
        x: { type: 'linear', title: { display: true, text: 'time', color: PLOT_STYLE.text },
             ticks: { color: PLOT_STYLE.text, maxTicksLimit: 6, callback: (t) => clockLabel(t) },
             grid: { color: PLOT_STYLE.grid } },
        y: { beginAtZero: true, title: { display: true, text: yTitle, color: PLOT_STYLE.text },
             ticks: { color: PLOT_STYLE.text, maxTicksLimit: 5 }, grid: { color: PLOT_STYLE.grid } },
      },
    },
  });
}

class VehiclePlots {
  constructor() {
    this.charts = {
      deviation: makeTimePlot(document.getElementById('plot-deviation'), '3σ (mm)', '#5dade2'),
      inliers: makeTimePlot(document.getElementById('plot-inliers'), 'inliers', '#2ecc71'),
      cycle: makeTimePlot(document.getElementById('plot-cycle'), 'p95 (ms)', '#f39c12'),
    };
  }

  // `history`: the answer of /api/vehicles/ID/history.
  show(history) {
    const series = (t, values) => t.map((x, i) => ({ x, y: values[i] }));
    this.set('deviation', series(history.poses.t, history.poses.deviation_m.map((d) => d * 1e3)));
    this.set('inliers', series(history.health.t, history.health.inliers));
    this.set('cycle', series(history.health.t, history.health.cycle_ms_p95));
  }

  set(name, points) {
    const chart = this.charts[name];
    chart.data.datasets[0].data = points;
    chart.update('none');
  }
}

window.VehiclePlots = VehiclePlots;
