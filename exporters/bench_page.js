// snag-bench's page: draws the charts and tables of the JSON that the page
// carries in the data-results attribute of #content. Self-check on <body>: data-ready="1"
// when done, data-charts (charts drawn), data-families, data-scenes,
// data-error when something failed. With #only=ID in the address only the
// figure of that id is shown, at a fixed size, for PNG screenshots.
(function () {
  'use strict';
  var body = document.body;
  var BENCH = JSON.parse(document.getElementById('content').getAttribute('data-results'));
  var COLOURS = {
    'cubic-float': '#d62728', 'cubic-double': '#ff7f0e', 'filter': '#1f77b4',
    'certified': '#2ca02c', 'exact': '#7f3fbf'
  };
  var POINTS = ['circle', 'rect', 'triangle', 'rectRot', 'star', 'crossRot', 'rectRounded', 'cross'];
  var charts = 0;
  var only = (/[#&]only=([^&]+)/.exec(location.hash) || [])[1];

  function el(tag, attributes, text) {
    var e = document.createElement(tag);
    Object.keys(attributes || {}).forEach(function (k) { e.setAttribute(k, attributes[k]); });
    if (text !== undefined) e.textContent = text;
    return e;
  }
  function methodLabel(id) {
    var m = BENCH.methods.filter(function (x) { return x.id === id; })[0];
    return m ? m.label : id;
  }
  function figure(parent, id, caption) {
    var f = el('figure', { id: id, 'class': 'chart' });
    var box = el('div', { 'class': 'chart-box' });
    var canvas = el('canvas');
    box.appendChild(canvas);
    f.appendChild(box);
    f.appendChild(el('figcaption', {}, caption));
    parent.appendChild(f);
    return canvas;
  }
  function draw(canvas, config) {
    config.options = config.options || {};
    config.options.animation = false;
    config.options.responsive = true;
    config.options.maintainAspectRatio = false;
    new Chart(canvas.getContext('2d'), config);
    ++charts;
  }
  function table(parent, header, rows) {
    var t = el('table');
    var tr = el('tr');
    header.forEach(function (h) { tr.appendChild(el('th', {}, h)); });
    t.appendChild(tr);
    rows.forEach(function (row) {
      var r = el('tr');
      row.forEach(function (c) { r.appendChild(el('td', {}, String(c))); });
      t.appendChild(r);
    });
    parent.appendChild(t);
  }
  function fixed(x, digits) { return typeof x === 'number' ? x.toFixed(digits) : x; }
  // Log axes: a label at each power of ten only.
  function powerTick(v) {
    var e = Math.log10(v);
    return Math.abs(e - Math.round(e)) < 1e-9 ? '1e' + Math.round(e) : '';
  }

  // The speed-accuracy charts: one point per method and data set.
  function speedChart(parent, id, field, title) {
    var sets = [];
    BENCH.query_sets.forEach(function (s) { sets.push({ name: s.name + ' ' + s.kind, queries: s.queries, methods: s.methods }); });
    BENCH.scenes.forEach(function (s) {
      sets.push({ name: s.name + ' (scene)', queries: s.vf_candidates + s.ee_candidates, methods: s.methods });
    });
    var smallest = 1;
    sets.forEach(function (s) {
      Object.keys(s.methods).forEach(function (m) {
        var share = s.methods[m][field] / Math.max(1, s.queries);
        if (share > 0) smallest = Math.min(smallest, share);
      });
    });
    var floor = Math.pow(10, Math.floor(Math.log10(smallest)) - 1);
    var datasets = BENCH.methods.map(function (m) {
      return {
        label: m.label, backgroundColor: COLOURS[m.id], borderColor: COLOURS[m.id],
        pointStyle: sets.map(function (s, i) { return POINTS[i % POINTS.length]; }), pointRadius: 5,
        data: sets.map(function (s) {
          var c = s.methods[m.id];
          return { x: Math.max(c.us_per_query, 1e-3), y: Math.max(c[field] / Math.max(1, s.queries), floor), set: s.name, count: c[field] };
        })
      };
    });
    draw(figure(parent, id, title + ' (zero drawn at the bottom line; one point per data set, shape = data set)'), {
      type: 'scatter', data: { datasets: datasets },
      options: {
        plugins: {
          title: { display: true, text: title },
          tooltip: { callbacks: { label: function (c) { return c.dataset.label + ', ' + c.raw.set + ': ' + c.raw.count + ' at ' + fixed(c.raw.x, 2) + ' us'; } } }
        },
        scales: {
          x: { type: 'logarithmic', title: { display: true, text: 'time per query (microseconds)' }, ticks: { callback: powerTick } },
          y: {
            type: 'logarithmic', min: floor, max: 1,
            title: { display: true, text: 'share of queries (' + (field === 'fn' ? 'false negatives' : 'false positives') + ')' },
            ticks: { callback: function (v) { return v === floor ? '0' : powerTick(v); } }
          }
        }
      }
    });
  }

  function speedSection() {
    var s = el('section', { id: 'speed' });
    s.appendChild(el('h2', {}, 'Speed against accuracy'));
    speedChart(s, 'speed-fn', 'fn', 'False negatives against time per query');
    speedChart(s, 'speed-fp', 'fp', 'False positives against time per query');
    var rows = [];
    BENCH.query_totals.concat(BENCH.query_sets).forEach(function (q) {
      BENCH.methods.forEach(function (m) {
        var c = q.methods[m.id];
        rows.push([q.name, q.kind, m.id, q.queries, c.fn, c.fp, c.uncertain, fixed(c.us_per_query, 2)]);
      });
    });
    table(s, ['data set', 'kind', 'method', 'queries', 'FN', 'FP', 'uncertain', 'us/query'], rows);
    document.getElementById('content').appendChild(s);
  }

  function familySection() {
    var s = el('section', { id: 'families' });
    s.appendChild(el('h2', {}, 'Stability: where each method starts to fail'));
    BENCH.families.forEach(function (f) {
      var datasets = BENCH.methods.map(function (m) {
        return {
          label: m.label, borderColor: COLOURS[m.id], backgroundColor: COLOURS[m.id], showLine: true, pointRadius: 3,
          data: f.knob_values.map(function (k, i) { return { x: k, y: f.methods[m.id].error_rate[i] }; })
        };
      });
      datasets.push({
        label: 'snag filter alone: uncertain', borderColor: COLOURS.filter, borderDash: [6, 4], showLine: true,
        pointRadius: 0, data: f.knob_values.map(function (k, i) { return { x: k, y: f.methods.filter.uncertain[i] / f.samples }; })
      });
      var title = f.name + ' (' + f.kind.toUpperCase() + ', ' + f.samples + ' samples per value)';
      draw(figure(s, 'family-' + f.name, f.description + ' (methods with no error overlap at 0)'), {
        type: 'scatter', data: { datasets: datasets },
        options: {
          plugins: { title: { display: true, text: title } },
          scales: {
            x: { type: 'logarithmic', title: { display: true, text: f.knob }, ticks: { callback: powerTick } },
            y: { min: 0, max: 1, title: { display: true, text: 'share of queries wrong (FN + FP)' } }
          }
        }
      });
    });
    document.getElementById('content').appendChild(s);
  }

  function sceneSection() {
    var s = el('section', { id: 'scenes' });
    s.appendChild(el('h2', {}, 'What each scene needed'));
    BENCH.scenes.forEach(function (scene, i) {
      s.appendChild(el('h3', {}, scene.name + ': ' + scene.steps + ' steps, ' + scene.triangles + ' triangles'));
      s.appendChild(el('p', {}, scene.description));
      var tiers = BENCH.tiers.map(function (t) { return scene.tiers[t]; });
      var total = tiers.reduce(function (a, b) { return a + b; }, 0) || 1;
      draw(figure(s, 'scene-' + i + '-tiers', 'Share of the grid\'s candidates decided at each tier'), {
        type: 'bar',
        data: { labels: BENCH.tiers, datasets: [{ label: scene.name, backgroundColor: '#1f77b4', data: tiers.map(function (n) { return n / total; }) }] },
        options: { plugins: { legend: { display: false } }, scales: { y: { type: 'logarithmic', title: { display: true, text: 'share of candidates' } } } }
      });
      table(s, ['run', 'candidates', 'exact queries', 'broad phase (s)', 'narrow phase (s)'], [
        ['adaptive (VSS grid, tiers)', scene.adaptive.candidates, scene.adaptive.exact_queries, fixed(scene.adaptive.broad_seconds, 4), fixed(scene.adaptive.narrow_seconds, 4)],
        ['heavy (complete set, exact for all)', scene.heavy.candidates, scene.heavy.exact_queries, fixed(scene.heavy.broad_seconds, 4), fixed(scene.heavy.narrow_seconds, 4)]
      ]);
      s.appendChild(el('p', { 'class': scene.same_answers ? 'same' : 'differ' },
        scene.same_answers ? 'Same answers: the adaptive run found exactly the ' + scene.positives + ' colliding pairs of the heavy run.'
          : 'The answers differ from the heavy run.'));
      var runs = scene.broad_phases.filter(function (r) { return !r.skipped; });
      draw(figure(s, 'scene-' + i + '-broad', 'Broad phases: pair tests and seconds (log scales)'), {
        type: 'bar',
        data: {
          labels: runs.map(function (r) { return r.name; }),
          datasets: [
            { label: 'tests', backgroundColor: '#1f77b4', yAxisID: 'tests', data: runs.map(function (r) { return Math.max(r.tests, 1); }) },
            { label: 'seconds', backgroundColor: '#ff7f0e', yAxisID: 'seconds', data: runs.map(function (r) { return Math.max(r.seconds, 1e-6); }) }
          ]
        },
        options: { scales: { tests: { type: 'logarithmic', position: 'left' }, seconds: { type: 'logarithmic', position: 'right' } } }
      });
      table(s, ['broad phase', 'tests', 'candidates', 'cells', 'levels', 'halvings', 'memory (MB)', 'seconds', 'missed'],
        scene.broad_phases.map(function (r) {
          return r.skipped ? [r.name, 'skipped', '', '', '', '', '', '', '']
            : [r.name, r.tests, r.candidates, r.cells_used, r.levels_used, r.time_halvings, fixed(r.memory_bytes / 1048576, 2), fixed(r.seconds, 4), r.missed];
        }));
    });
    document.getElementById('content').appendChild(s);
  }

  try {
    speedSection();
    familySection();
    sceneSection();
    if (only) {
      var shown = document.getElementById(decodeURIComponent(only));
      if (!shown) throw new Error('no figure ' + only);
      body.className = 'only';
      document.getElementById('content').style.display = 'none';
      document.body.appendChild(shown);
    }
  } catch (e) {
    body.setAttribute('data-error', String(e && e.message || e));
  }
  body.setAttribute('data-charts', String(charts));
  body.setAttribute('data-families', String(BENCH.families.length));
  body.setAttribute('data-scenes', String(BENCH.scenes.length));
  body.setAttribute('data-ready', '1');
})();
