// rockwatch dashboard page: one WebSocket (/ws) gives the whole state first, then per-wall updates (at most 30 per
// second per wall); each wall is a card with the level banner, the values, x(t) and E/E_barrier charts (uPlot) over
// the last history_s seconds (and P(collapse) when the monitor runs --forecast), the alarm transitions and the
// monitor's status. Points carry ids: an update re-sends
// the last point when the server replaced it (the larger |x| of its time bin), so merging is by id.
'use strict';

(function () {
  const LEVELS = ['QUIET', 'ROCKING', 'WARNING', 'IMMINENT', 'COLLAPSED'];
  const COLORS = { x: '#1565c0', measured: '#6a1b9a', inst: '#ef6c00', warning: '#f9a825', collapse: '#b71c1c',
    energy: '#00695c', barrier: '#ef6c00', margin: '#b71c1c', forecast: '#4a148c' };
  const haveCharts = typeof window.uPlot === 'function';
  const walls = new Map();  // name -> wall view
  let historyS = 30;
  let renderQueued = false;

  const $ = (tag, cls, text) => {
    const el = document.createElement(tag);
    if (cls) el.className = cls;
    if (text !== undefined) el.textContent = text;
    return el;
  };
  const fmt = (v, digits, unit) => {
    if (v === null || v === undefined || !isFinite(v)) return '—';
    const r = Number(v.toFixed(digits));  // no "-0.0"
    return (r === 0 ? 0 : r).toFixed(digits) + (unit ? ' ' + unit : '');
  };
  const mm = (m) => fmt(m === null ? null : m * 1000, 1, 'mm');
  const clock = (t) => new Date(t * 1000).toISOString().substring(11, 23);

  function chartWidth(el) { return Math.max(300, el.clientWidth || 600); }

  function makeXChart(el, limits) {
    const dash = [6, 4];
    const line = (label, stroke, d) => ({ label, stroke, width: 1, dash: d, points: { show: false } });
    return new uPlot({
      width: chartWidth(el), height: 260,
      scales: { x: { time: true }, y: { range: () => {
        const c = Math.max(limits.x_collapse_m[0], limits.x_collapse_m[1]) * 1.1;
        return [-c, c];
      } } },
      axes: [{}, { label: 'x [m]', size: 60 }],
      series: [{}, { label: 'x predicted', stroke: COLORS.x, width: 2, spanGaps: false },
        { label: 'x measured', stroke: COLORS.measured, width: 1, spanGaps: true },
        line('+x_inst', COLORS.inst, null), line('−x_inst', COLORS.inst, null),
        line('+warning', COLORS.warning, dash), line('−warning', COLORS.warning, dash),
        line('+collapse', COLORS.collapse, dash), line('−collapse', COLORS.collapse, dash),
        line('+x_inst estimated', COLORS.inst, [2, 3]), line('−x_inst estimated', COLORS.inst, [2, 3])],
      legend: { live: false },
    }, [[], [], [], [], [], [], [], [], [], [], []], el);
  }

  function makeEChart(el, limits) {
    return new uPlot({
      width: chartWidth(el), height: 260,
      scales: { x: { time: true }, y: { range: (u, min, max) => [0, Math.max(limits.energy_margin * 1.2, max || 0)] } },
      axes: [{}, { label: 'E / E_barrier', size: 50 }],
      series: [{}, { label: 'E/E_barrier', stroke: COLORS.energy, width: 2 },
        { label: 'barrier', stroke: COLORS.barrier, width: 1, points: { show: false } },
        { label: 'margin', stroke: COLORS.margin, width: 1, dash: [6, 4], points: { show: false } }],
      legend: { live: false },
    }, [[], [], [], []], el);
  }

  // P(collapse within H) of the monitor's forecast (wall_forecast_t), 0 to 1: the calibrated P (SPEC §10, the odds
  // to read) and the ensemble's raw fraction, over-confident above 0.5 (docs/BENCHMARKS.md "Forecast").
  function makePChart(el) {
    return new uPlot({
      width: chartWidth(el), height: 180,
      scales: { x: { time: true }, y: { range: () => [0, 1] } },
      axes: [{}, { label: 'P(collapse)', size: 50 }],
      series: [{},
        { label: 'P(collapse within H), calibrated', stroke: COLORS.forecast, width: 2, spanGaps: false },
        { label: 'ensemble fraction (raw)', stroke: COLORS.forecast, width: 1, dash: [4, 4], spanGaps: false }],
      legend: { live: false },
    }, [[], [], []], el);
  }

  function makeWall(name) {
    const card = $('section', 'wall');
    card.dataset.wall = name;
    card.appendChild($('h2', null, 'wall "' + name + '"'));
    const row = $('div', 'banner-row');
    const level = $('div', 'level level-unknown', '—');
    level.dataset.testid = 'level';
    level.dataset.wall = name;
    row.appendChild(level);
    const values = $('div', 'values');
    const value = (key, label, cls) => {
      const d = $('div', cls);
      d.appendChild($('span', 'k', label));
      const v = $('span', 'v', '—');
      v.dataset.testid = key;
      v.dataset.wall = name;
      d.appendChild(v);
      values.appendChild(d);
      return v;
    };
    const view = { name, card, level, points: [], measured: [], forecast: [], transitions: [], status: null,
      restarts: null };
    view.tInst = value('t-to-instability', 'time to instability', 'countdown');
    view.x = value('x', 'x (mid-height)');
    view.xd = value('xd', 'ẋ');
    view.energy = value('energy', 'E / E_barrier');
    view.reasons = value('reasons', 'reasons');
    view.time = value('time', 'sample time (UTC)');
    view.quality = value('quality', 'data quality (sample)');
    view.estimate = value('estimate', 'observer');
    view.pCollapse = value('p-collapse', 'P(collapse), forecast');
    row.appendChild(values);
    card.appendChild(row);
    const charts = $('div', 'charts');
    const xBox = $('div'), eBox = $('div');
    xBox.appendChild($('p', 'chart-title', 'x(t), last ' + historyS + ' s: ±x_inst, warning and collapse limits'));
    eBox.appendChild($('p', 'chart-title', 'E / E_barrier: barrier at 1, energy margin dashed'));
    view.xEl = $('div', 'chart');
    view.xEl.dataset.testid = 'x-chart';
    view.xEl.dataset.wall = name;
    view.xEl.dataset.points = '0';
    view.eEl = $('div', 'chart');
    view.eEl.dataset.testid = 'energy-chart';
    view.eEl.dataset.wall = name;
    xBox.appendChild(view.xEl);
    eBox.appendChild(view.eEl);
    charts.appendChild(xBox);
    charts.appendChild(eBox);
    card.appendChild(charts);
    const pBox = $('div', 'forecast-box');
    pBox.appendChild($('p', 'chart-title', 'P(collapse within the horizon): the monitor\'s forecast, calibrated ' +
      '(solid) and the ensemble\'s raw fraction (dashed) (rockwatch-monitor --forecast; 0 while the wall is at rest)'));
    view.pEl = $('div', 'chart');
    view.pEl.dataset.testid = 'forecast-chart';
    view.pEl.dataset.wall = name;
    view.pEl.dataset.points = '0';
    pBox.appendChild(view.pEl);
    pBox.hidden = true;  // shown at the first forecast
    view.pBox = pBox;
    card.appendChild(pBox);
    // The observer's sensors (wall_estimate_t): per sensor its last innovation, the innovation's σ, the test ratio
    // (above 1 the χ² gate rejects), the verdict and when a reading of it last corrected the state. Hidden until the
    // first estimate (the monitor runs the observer).
    view.sensorsBox = $('div', 'sensors-box');
    view.sensorsBox.appendChild($('p', 'chart-title', 'observer sensors: last reading tried against the model ' +
      '(test ratio = innovation² / (gate · variance); above 1 the gate rejects it) and the last accepted one'));
    view.sensorsEl = $('div', 'sensors');
    view.sensorsEl.dataset.testid = 'observer-sensors';
    view.sensorsEl.dataset.wall = name;
    view.sensorsBox.appendChild(view.sensorsEl);
    view.sensorsBox.hidden = true;
    card.appendChild(view.sensorsBox);
    const lists = $('div', 'lists');
    const tBox = $('div'), sBox = $('div');
    tBox.appendChild($('p', 'chart-title', 'alarm transitions (latest first; the last 50)'));
    view.transitionsEl = $('div', 'transitions');
    view.transitionsEl.dataset.testid = 'transitions';
    view.transitionsEl.dataset.wall = name;
    tBox.appendChild(view.transitionsEl);
    sBox.appendChild($('p', 'chart-title', 'monitor status (data quality since the previous status; counters since start)'));
    view.statusEl = $('div', 'status');
    view.statusEl.dataset.testid = 'status';
    view.statusEl.dataset.wall = name;
    sBox.appendChild(view.statusEl);
    lists.appendChild(tBox);
    lists.appendChild(sBox);
    card.appendChild(lists);
    // Keep the cards in name order.
    const container = document.getElementById('walls');
    const after = [...container.children].find((c) => c.dataset.wall > name);
    container.insertBefore(card, after || null);
    document.getElementById('waiting').hidden = true;
    walls.set(name, view);
    return view;
  }

  function mergePoints(list, incoming) {
    for (const p of incoming) {
      const last = list.length ? list[list.length - 1] : null;
      if (last && last[0] === p[0]) list[list.length - 1] = p;
      else if (!last || p[0] > last[0]) list.push(p);
    }
  }

  function prune(list, latestT) {
    let drop = 0;
    while (drop < list.length && list[drop][1] < latestT - historyS) ++drop;
    if (drop) list.splice(0, drop);
  }

  function applyWall(w, whole) {
    const view = walls.get(w.name) || makeWall(w.name);
    const restarts = w.counters ? w.counters.monitor_restarts : null;
    if (whole || (view.restarts !== null && restarts !== view.restarts)) {
      view.points = [];
      view.measured = [];
      view.forecast = [];
    }
    view.restarts = restarts;
    view.data = w;
    view.limits = w.limits;
    mergePoints(view.points, w.points || []);
    mergePoints(view.measured, w.measured || []);
    mergePoints(view.forecast, w.forecast_points || []);
    const latest = Math.max(view.points.length ? view.points[view.points.length - 1][1] : -Infinity,
      view.measured.length ? view.measured[view.measured.length - 1][1] : -Infinity);
    if (isFinite(latest)) { prune(view.points, latest); prune(view.measured, latest); prune(view.forecast, latest); }
    if (w.transitions) view.transitions = w.transitions;
    else if (w.transitions_total !== undefined && view.transitionsTotal !== undefined &&
             w.transitions_total !== view.transitionsTotal && !whole) {
      refetch();  // an update with the transitions was dropped on the way: take the whole state again
    }
    if (w.transitions) view.transitionsTotal = w.transitions_total;
    if ('status' in w) view.status = w.status;
    view.dirty = true;
  }

  function renderWall(view) {
    const w = view.data;
    const level = w.level;
    view.level.textContent = level;
    view.level.className = 'level ' + (LEVELS.includes(level) ? 'level-' + level : 'level-unknown');
    view.tInst.textContent = w.t_to_instability_s === null ? 'none' : fmt(w.t_to_instability_s, 2, 's');
    view.x.textContent = mm(w.x_m);
    view.xd.textContent = fmt(w.xd_mps === null ? null : w.xd_mps * 1000, 1, 'mm/s');
    view.energy.textContent = fmt(w.energy_ratio, 3);
    view.reasons.textContent = w.reasons.length ? w.reasons.join(', ') : 'none';
    view.time.textContent = w.t_s === null ? '—' : clock(w.t_s);
    view.quality.textContent = w.data_quality.length ? w.data_quality.join(', ') : 'ok';
    view.estimateData = w.estimate || null;
    view.estimate.textContent = w.estimate ? 'σx ' + mm(w.estimate.sigma_x_m) + ', r ' + fmt(w.estimate.r_estimate, 3) +
      (w.estimate.x_inst_estimate_m != null ? ', x_inst ' + mm(w.estimate.x_inst_estimate_m) + ' ± ' +
        mm(w.estimate.sigma_x_inst_m) : '') +
      (w.estimate.sensor_health.length ? ' (' + w.estimate.sensor_health.join(', ') + ')' : '') : 'off';
    const f = w.forecast;
    const calibrated = f && f.p_collapse_calibrated != null ? fmt(f.p_collapse_calibrated, 3) + ' calibrated, ' : '';
    view.pCollapse.textContent = !f ? 'off' : f.status === 'ok' ?
      calibrated + 'ensemble ' + fmt(f.p_collapse, 3) + ' ± ' + fmt(f.p_collapse_se, 3) + ' within ' +
        fmt(f.horizon_s, 1, 's') + ' (' + f.members + ' members from the ' +
        (f.fused ? 'fused state and its σ' : 'model\'s state') + ', ' + fmt(f.compute_us / 1000, 1, 'ms') + ')' :
      f.status === 'at_rest' ? 'wall at rest' : f.status === 'collapsed' ? '1 (collapsed)' : 'waiting for input';
    if (f) view.pBox.hidden = false;
    renderSensors(view);
    renderTransitions(view);
    renderStatus(view);
    if (haveCharts) renderCharts(view);
    view.xEl.dataset.points = String(view.points.length);
    view.pEl.dataset.points = String(view.forecast.length);
    view.pEl.dataset.calibrated = String(view.forecast.filter((p) => p[3] != null).length);
  }

  function renderCharts(view) {
    const L = view.limits;
    if (!view.xChart) {
      view.xChart = makeXChart(view.xEl, L);
      view.eChart = makeEChart(view.eEl, L);
    }
    const pred = [view.points.map((p) => p[1]), view.points.map((p) => p[2])];
    const meas = [view.measured.map((p) => p[1]), view.measured.map((p) => p[2])];
    const joined = meas[0].length ? uPlot.join([pred, meas]) : [pred[0], pred[1], pred[0].map(() => null)];
    const n = joined[0].length;
    const constant = (v) => new Array(n).fill(v);
    // The observer's estimated x_inst (side +1, the wall_estimate_t of the last sample; side −1 by the same κc/κk),
    // beside the nominal one.
    const est = view.estimateData;
    const xEst = est && est.x_inst_estimate_m != null ? est.x_inst_estimate_m : null;
    view.xChart.setData([joined[0], joined[1], joined[2], constant(L.x_inst_m[1]), constant(-L.x_inst_m[0]),
      constant(L.x_warning_m[1]), constant(-L.x_warning_m[0]), constant(L.x_collapse_m[1]),
      constant(-L.x_collapse_m[0]), constant(xEst), constant(xEst === null ? null : -xEst * L.x_inst_m[0] / L.x_inst_m[1])]);
    const t = pred[0];
    view.eChart.setData([t, view.points.map((p) => p[3]), t.map(() => L.energy_barrier),
      t.map(() => L.energy_margin)]);
    view.xEl.dataset.plotted = String(view.xChart.data[0].length);
    if (view.forecast.length || view.pChart) {
      if (!view.pChart) view.pChart = makePChart(view.pEl);
      view.pChart.setData([view.forecast.map((p) => p[1]), view.forecast.map((p) => p[3]),
        view.forecast.map((p) => p[2])]);
    }
  }

  function renderTransitions(view) {
    const table = $('table');
    const head = $('tr');
    for (const h of ['time (UTC)', 'level', 'from', 'x', 'E/E_b', 't_inst', 'reasons']) head.appendChild($('th', null, h));
    table.appendChild(head);
    for (const e of [...view.transitions].reverse()) {
      const tr = $('tr');
      tr.dataset.level = e.level;
      for (const v of [clock(e.t_s), e.level, e.previous_level, mm(e.x_m), fmt(e.energy_ratio, 3),
        e.t_to_instability_s === null ? '—' : fmt(e.t_to_instability_s, 2, 's'), e.reasons.join(', ')]) {
        tr.appendChild($('td', null, v));
      }
      table.appendChild(tr);
    }
    view.transitionsEl.replaceChildren(table);
  }

  // One row per observer sensor: x (displacement transducer, mm) and a (accelerometer, m/s²).
  function renderSensors(view) {
    const est = view.estimateData;
    if (!est || !est.sensors) { view.sensorsBox.hidden = true; return; }
    view.sensorsBox.hidden = false;
    const table = $('table', 'sensor-status');
    const head = $('tr');
    for (const h of ['sensor', 'innovation', 'σ innovation', 'test ratio', 'gate', 'last fused (UTC)']) {
      head.appendChild($('th', null, h));
    }
    table.appendChild(head);
    const rows = [['x', 'displacement', (v) => mm(v)], ['a', 'acceleration', (v) => fmt(v, 3, 'm/s²')]];
    for (const [key, label, show] of rows) {
      const s = est.sensors[key];
      if (!s) continue;
      const tried = s.innovation_variance !== null && s.innovation_variance > 0;
      const tr = $('tr', s.rejected ? 'rejected' : '');
      tr.dataset.sensor = key;
      tr.appendChild($('td', null, label));
      tr.appendChild($('td', null, tried ? show(s.innovation) : '—'));
      tr.appendChild($('td', null, tried ? show(Math.sqrt(s.innovation_variance)) : '—'));
      tr.appendChild($('td', null, tried ? fmt(s.test_ratio, 2) : '—'));
      tr.appendChild($('td', null, !tried ? 'none yet' : s.rejected ? 'rejected' : 'passed'));
      tr.appendChild($('td', null, s.last_fused_utime === null ? 'never' : clock(s.last_fused_utime / 1e6)));
      table.appendChild(tr);
    }
    view.sensorsEl.replaceChildren(table);
  }

  function renderStatus(view) {
    const s = view.status;
    if (!s) { view.statusEl.replaceChildren($('p', 'notice', 'no status yet (the monitor sends one per second)')); return; }
    const flags = $('div', 'flags');
    if (s.data_quality.length) for (const f of s.data_quality) flags.appendChild($('span', null, f));
    else flags.appendChild($('span', 'none', 'no data-quality flags'));
    const info = $('p', 'notice', 'rockwatch-monitor ' + s.version + ', ' + s.arithmetic + ' engine, level ' +
      s.alarm_level + ', worst step ' + fmt(s.worst_step_ns / 1000, 1, 'µs') + ', status #' + s.seq);
    const table = $('table', 'counters');
    // Counters that are not 0 are the ones to look at; samples_* always show.
    for (const [k, v] of Object.entries(s.counters)) {
      if (v === 0 && !k.startsWith('samples_')) continue;
      const tr = $('tr', v !== 0 && !k.startsWith('samples_') ? 'nonzero' : '');
      tr.appendChild($('td', null, k));
      tr.appendChild($('td', null, String(v)));
      table.appendChild(tr);
    }
    view.statusEl.replaceChildren(flags, info, table);
  }

  function scheduleRender() {
    if (renderQueued) return;
    renderQueued = true;
    requestAnimationFrame(() => {
      renderQueued = false;
      for (const view of walls.values()) {
        if (view.dirty) { view.dirty = false; renderWall(view); }
      }
    });
  }

  function applyState(state) {
    historyS = state.history_s || historyS;
    const names = new Set(state.walls.map((w) => w.name));
    for (const [name, view] of walls) {
      if (!names.has(name)) { view.card.remove(); walls.delete(name); }
    }
    for (const w of state.walls) applyWall(w, true);
    if (state.server) {
      document.getElementById('server').textContent = 'at page load: pages ' + state.server.ws_clients + ', updates sent ' +
        state.server.ws_messages_sent + ', dropped ' + state.server.ws_messages_dropped;
    }
    scheduleRender();
  }

  let refetching = false;
  function refetch() {
    if (refetching) return;
    refetching = true;
    fetch('/api/state').then((r) => r.json()).then(applyState).catch(() => {}).finally(() => { refetching = false; });
  }

  function setConnection(cls, text) {
    const el = document.getElementById('connection');
    el.className = 'conn ' + cls;
    el.textContent = text;
  }

  function connect() {
    const ws = new WebSocket((location.protocol === 'https:' ? 'wss://' : 'ws://') + location.host + '/ws');
    ws.onopen = () => setConnection('conn-live', 'live');
    ws.onmessage = (event) => {
      let m;
      try { m = JSON.parse(event.data); } catch (e) { return; }
      if (m.type === 'state') applyState(m);
      else if (m.type === 'update') { applyWall(m.wall, false); scheduleRender(); }
    };
    ws.onclose = () => {
      setConnection('conn-lost', 'connection lost: retrying');
      setTimeout(connect, 1000);
    };
  }

  if (!haveCharts) document.getElementById('no-charts').hidden = false;
  window.addEventListener('resize', () => {
    for (const v of walls.values()) {
      if (v.xChart) {
        v.xChart.setSize({ width: chartWidth(v.xEl), height: 260 });
        v.eChart.setSize({ width: chartWidth(v.eEl), height: 260 });
        if (v.pChart) v.pChart.setSize({ width: chartWidth(v.pEl), height: 180 });
      }
    }
  });
  connect();
})();
