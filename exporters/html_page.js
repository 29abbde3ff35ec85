// The script of snag-report's HTML page (html.cpp inlines it after Chart.js,
// three.js and OrbitControls). It reads the reports from the JSON in
// <script id="snag-data"> and fills each <section class="report">: key
// numbers, the chart of events and regions per frame, the tracks table and
// the 3D view. When it has drawn, it sets the self-check attributes on <body>
// and on each section (html.hpp lists them); a part that fails shows its
// error and sets data-error, the others still draw.
(function () {
  'use strict';

  var COLLISION = '#e8590c', INTERSECTION = '#6741d9';
  var COLLISION_REGION = '#ffc078', INTERSECTION_REGION = '#b197fc';
  var errors = [];

  function el(tag, attrs, children) {
    var node = document.createElement(tag);
    if (attrs) Object.keys(attrs).forEach(function (key) {
      if (key === 'text') node.textContent = attrs[key];
      else if (key === 'class') node.className = attrs[key];
      else node.setAttribute(key, attrs[key]);
    });
    (children || []).forEach(function (child) {
      node.appendChild(typeof child === 'string' ? document.createTextNode(child) : child);
    });
    return node;
  }
  function fmt(n) {
    if (n === null || n === undefined) return '\u2013';
    return typeof n === 'number' ? n.toLocaleString('en-US', { maximumSignificantDigits: 6 }) : String(n);
  }
  function vec(v) {
    return v ? '(' + v.map(function (x) { return x.toLocaleString('en-US', { maximumSignificantDigits: 3 }); }).join(', ') + ')' : '\u2013';
  }
  function decode(b64, Type) {
    var text = atob(b64), bytes = new Uint8Array(text.length);
    for (var i = 0; i < text.length; ++i) bytes[i] = text.charCodeAt(i);
    return new Type(bytes.buffer);
  }
  /// One colour per region of a frame: golden-angle hues.
  function regionHue(k) { return ((k * 137.508) + 20) % 360; }
  function regionCss(k) { return 'hsl(' + regionHue(k).toFixed(1) + ', 80%, 48%)'; }
  function report_error(where, container, e) {
    var text = where + ': ' + (e && e.message ? e.message : String(e));
    errors.push(text);
    if (container) container.appendChild(el('div', { class: 'error', text: text }));
    if (window.console) console.error(text, e);
  }

  var webglAvailable = (function () {
    try {
      var canvas = document.createElement('canvas');
      return !!(window.WebGLRenderingContext && (canvas.getContext('webgl2') || canvas.getContext('webgl')));
    } catch (e) { return false; }
  })();

  // ---- key numbers, rules and pairs ----
  function renderOverview(report, body) {
    var t = report.totals, th = report.thresholds;
    var tiles = el('div', { class: 'tiles' });
    function tile(label, value, threshold) {
      var over = threshold > 0 && value >= threshold;
      tiles.appendChild(el('div', { class: 'tile' + (over ? ' over' : '') }, [
        el('b', { text: fmt(value) }), label,
        threshold > 0 ? el('small', { text: ' (fails at ' + fmt(threshold) + ')' }) : ''
      ]));
    }
    tile('frames', t.frames, 0);
    tile('events', t.events, th.events);
    tile('collisions', t.collisions, th.collisions);
    tile('intersections', t.intersections, th.intersections);
    tile('regions', t.regions, th.regions);
    tile('tracks', t.tracks, th.tracks);
    tile('allowed', t.allowed, 0);
    if (t.uncertain) tile('uncertain', t.uncertain, 0);
    body.appendChild(tiles);
    var objects = report.objects.map(function (o) {
      return o.name + ' (' + fmt(o.vertices) + ' vertices, ' + fmt(o.triangles) + ' triangles)';
    }).join(', ');
    var s = report.settings;
    body.appendChild(el('p', { class: 'note', text: 'Objects: ' + objects + '. Scan: ' + s.mode + ', ' +
      s.precision + ', ' + s.backend + (s.frames ? ', frames ' + s.frames : '') +
      (s.manifest ? ', manifest ' + s.manifest : '') + (report.certified ? ', every event certified' : '') +
      '. snag ' + report.snag_version + '.' }));
    if (t.not_checked || t.neighbourhood)
      body.appendChild(el('p', { class: 'note', text: 'Not checked by the rules: ' + fmt(t.not_checked) +
        ' events of unchecked pairs, ' + fmt(t.neighbourhood) + ' within the neighbourhood.' }));
    if (!report.pairs.length) return;
    var table = el('table', { class: 'pairs' });
    table.appendChild(el('thead', {}, [el('tr', {}, ['pair', 'kind', 'events', 'allowed', 'regions', 'tracks',
      'frames', 'worst frame'].map(function (h, i) { return el('th', { class: i < 2 ? 'text' : '', text: h }); }))]));
    var tbody = el('tbody');
    report.pairs.forEach(function (p) {
      tbody.appendChild(el('tr', {}, [
        el('td', { text: p.objects }), el('td', { class: 'text', text: p.kind }), el('td', { text: fmt(p.events) }),
        el('td', { text: fmt(p.allowed) }), el('td', { text: fmt(p.regions) }), el('td', { text: fmt(p.tracks) }),
        el('td', { text: fmt(p.frames) }),
        el('td', { text: p.worst_frame === null ? '\u2013' : p.worst_frame + ' (' + fmt(p.worst_frame_events) + ' events)' })
      ]));
    });
    table.appendChild(tbody);
    body.appendChild(table);
  }

  // ---- chart of events and regions per frame ----
  function renderChart(report, body, state) {
    body.appendChild(el('h3', { text: 'Events and regions per frame' }));
    body.appendChild(el('p', { class: 'note', text: 'Collisions are counted at the frame their step starts. ' +
      'Bars on the left axis: events; on the right axis: regions. Click a frame to select it.' }));
    var frames = report.frames;
    if (typeof Chart === 'undefined') throw new Error('Chart.js is missing from the page');
    var box = el('div', { class: 'chart' }), canvas = el('canvas');
    box.appendChild(canvas);
    body.appendChild(box);
    var selectedPlugin = {
      id: 'snagSelectedFrame',
      beforeDatasetsDraw: function (chart) {
        var at = frames.index.indexOf(state.frame);
        if (at < 0) return;
        var x = chart.scales.x, area = chart.chartArea;
        var width = Math.max(3, (x.width / Math.max(1, frames.index.length)));
        var ctx = chart.ctx;
        ctx.save();
        ctx.fillStyle = 'rgba(9, 105, 218, 0.16)';
        ctx.fillRect(x.getPixelForValue(at) - width / 2, area.top, width, area.bottom - area.top);
        ctx.restore();
      }
    };
    var chart = new Chart(canvas, {
      type: 'bar',
      data: {
        labels: frames.index,
        datasets: [
          { label: 'collisions', data: frames.collisions, backgroundColor: COLLISION, stack: 'events', yAxisID: 'y' },
          { label: 'intersections', data: frames.intersections, backgroundColor: INTERSECTION, stack: 'events', yAxisID: 'y' },
          { label: 'collision regions', data: frames.collision_regions, backgroundColor: COLLISION_REGION, stack: 'regions', yAxisID: 'y1' },
          { label: 'intersection regions', data: frames.intersection_regions, backgroundColor: INTERSECTION_REGION, stack: 'regions', yAxisID: 'y1' }
        ]
      },
      options: {
        animation: false,
        responsive: true,
        maintainAspectRatio: false,
        interaction: { mode: 'index', intersect: false },
        scales: {
          x: { stacked: true, title: { display: true, text: 'frame' } },
          y: { stacked: true, position: 'left', beginAtZero: true, title: { display: true, text: 'events' } },
          y1: { stacked: true, position: 'right', beginAtZero: true, grid: { drawOnChartArea: false },
                title: { display: true, text: 'regions' } }
        },
        plugins: { legend: { position: 'top' } },
        onClick: function (event, elements, c) {
          var points = c.getElementsAtEventForMode(event, 'index', { intersect: false }, false);
          if (points.length) state.select(frames.index[points[0].index]);
        }
      },
      plugins: [selectedPlugin]
    });
    state.chart = chart;
    return chart.data.labels.length;
  }

  // ---- tracks table ----
  var TRACK_COLUMNS = [
    { key: 'id', label: 'track' },
    { key: 'objects', label: 'objects', text: true },
    { key: 'kind', label: 'kind', text: true },
    { key: 'first_frame', label: 'frames', show: function (t) { return t.first_frame + '\u2013' + t.last_frame; } },
    { key: 'frames', label: 'length' },
    { key: 'events', label: 'events' },
    { key: 'regions', label: 'regions' },
    { key: 'max_faces', label: 'largest (faces)' },
    { key: 'worst_frame', label: 'worst frame' },
    { key: 'centroid', label: 'position', sort: function (t) { return t.centroid[0]; }, show: function (t) { return vec(t.centroid); } },
    { key: 'size', label: 'extent', sort: function (t) { return Math.max.apply(null, t.size); }, show: function (t) { return vec(t.size); } },
    { key: 'toi', label: 'time of impact' }
  ];

  function renderTracks(report, body, state) {
    body.appendChild(el('h3', { text: 'Tracks (' + fmt(report.tracks.length) + ')' }));
    body.appendChild(el('p', { class: 'note', text: 'A track is a problem followed over consecutive frames: ' +
      'the regions of one pair and kind that share faces. Highlighted: the tracks of the selected frame. ' +
      'Click a header to sort, a row to show its worst frame.' +
      (report.merged_tracks === 1 ? ' 1 track merged into another is counted in it.' : '') +
      (report.merged_tracks > 1 ? ' ' + fmt(report.merged_tracks) + ' tracks merged into others are counted in them.' : '') }));
    if (!report.tracks.length) {
      body.appendChild(el('p', { text: 'No tracks.' }));
      return 0;
    }
    var wrap = el('div', { class: 'table-wrap' });
    var table = el('table', { class: 'sortable tracks' });
    var headRow = el('tr');
    var tbody = el('tbody');
    var rows = report.tracks.slice();
    var sortKey = 'events', descending = true;
    function value(column, t) { return column.sort ? column.sort(t) : t[column.key]; }
    function draw() {
      var column = TRACK_COLUMNS.filter(function (c) { return c.key === sortKey; })[0];
      rows.sort(function (a, b) {
        var x = value(column, a), y = value(column, b);
        if (x === y) return a.id - b.id;
        if (x === null) return 1;
        if (y === null) return -1;
        var order = x < y ? -1 : 1;
        return descending ? -order : order;
      });
      Array.prototype.forEach.call(headRow.children, function (th, i) {
        th.className = (TRACK_COLUMNS[i].text ? 'text ' : '') +
          (TRACK_COLUMNS[i].key === sortKey ? (descending ? 'sorted-down' : 'sorted-up') : '');
      });
      tbody.textContent = '';
      rows.forEach(function (t) {
        var tr = el('tr', { class: 'clickable', 'data-track': t.id }, TRACK_COLUMNS.map(function (c) {
          return el('td', { class: c.text ? 'text' : '', text: c.show ? c.show(t) : fmt(t[c.key]) });
        }));
        tr.addEventListener('click', function () { state.select(t.worst_frame); });
        tbody.appendChild(tr);
      });
      state.markTracks();
    }
    TRACK_COLUMNS.forEach(function (c) {
      var th = el('th', { text: c.label });
      th.addEventListener('click', function () {
        if (sortKey === c.key) descending = !descending;
        else { sortKey = c.key; descending = !c.text; }
        draw();
      });
      headRow.appendChild(th);
    });
    table.appendChild(el('thead', {}, [headRow]));
    table.appendChild(tbody);
    wrap.appendChild(table);
    body.appendChild(wrap);
    state.trackRows = tbody;
    state.tracksById = {};
    report.tracks.forEach(function (t) { state.tracksById[t.id] = t; });
    draw();
    return tbody.children.length;
  }

  // ---- 3D view ----
  function FrameGeometry(view) {
    this.objects = view.objects.map(function (o) { return { name: o.name, index: decode(o.index, Uint32Array) }; });
    this.frames = view.frames.slice().sort(function (a, b) { return a.frame - b.frame; });
    this.cache = {};
  }
  FrameGeometry.prototype.positions = function (frame) {
    if (!this.cache[frame]) {
      var record = this.frames.filter(function (f) { return f.frame === frame; })[0];
      this.cache[frame] = record ? record.positions.map(function (p) { return decode(p, Float32Array); }) : null;
    }
    return this.cache[frame];
  };
  FrameGeometry.prototype.bounds = function (frame) {
    var lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    this.positions(frame).forEach(function (p) {
      for (var i = 0; i + 2 < p.length; i += 3)
        for (var k = 0; k < 3; ++k) { lo[k] = Math.min(lo[k], p[i + k]); hi[k] = Math.max(hi[k], p[i + k]); }
    });
    if (lo[0] > hi[0]) { lo = [-1, -1, -1]; hi = [1, 1, 1]; }
    return { lo: lo, hi: hi, centre: [0, 1, 2].map(function (k) { return 0.5 * (lo[k] + hi[k]); }),
             diagonal: Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) || 1 };
  };
  /// Region triangles of `frame`: per region, the corners of its faces (9 floats each).
  FrameGeometry.prototype.regionTriangles = function (regions, frame) {
    var self = this, positions = this.positions(frame), out = [];
    regions.forEach(function (region) {
      var corners = [];
      region.faces.forEach(function (entry) {
        var faces = decode(entry.faces, Uint32Array), index = self.objects[entry.object].index, p = positions[entry.object];
        for (var i = 0; i < faces.length; ++i)
          for (var c = 0; c < 3; ++c) {
            var v = index[3 * faces[i] + c];
            corners.push(p[3 * v], p[3 * v + 1], p[3 * v + 2]);
          }
      });
      out.push(corners);
    });
    return out;
  };

  function WebGLView(container, geometry) {
    var width = container.clientWidth || 860, height = container.clientHeight || 560;
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.renderer.setSize(width, height);
    this.renderer.setClearColor(0xfbfbfc, 1);
    container.appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(40, width / height, 0.001, 1000);
    this.camera.add(new THREE.DirectionalLight(0xffffff, 0.65));
    this.scene.add(this.camera);
    this.scene.add(new THREE.AmbientLight(0xffffff, 0.45));
    this.controls = new THREE.OrbitControls(this.camera, this.renderer.domElement);
    this.controls.addEventListener('change', this.render.bind(this));
    this.geometry = geometry;
    var self = this;
    this.meshes = geometry.objects.map(function (object, o) {
      var g = new THREE.BufferGeometry();
      g.setIndex(new THREE.BufferAttribute(object.index, 1));
      var colour = new THREE.Color().setHSL((0.58 + 0.13 * o) % 1, 0.12, 0.72);
      var mesh = new THREE.Mesh(g, new THREE.MeshPhongMaterial({
        color: colour, side: THREE.DoubleSide, flatShading: true, shininess: 10,
        polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1 }));
      self.scene.add(mesh);
      return mesh;
    });
    this.overlay = new THREE.Mesh(new THREE.BufferGeometry(), new THREE.MeshPhongMaterial({
      vertexColors: THREE.VertexColors, side: THREE.DoubleSide, flatShading: true, shininess: 10 }));
    this.scene.add(this.overlay);
    this.framed = false;
  }
  WebGLView.prototype.render = function () { this.renderer.render(this.scene, this.camera); };
  WebGLView.prototype.show = function (frame, regions) {
    var positions = this.geometry.positions(frame);
    this.meshes.forEach(function (mesh, o) {
      mesh.geometry.setAttribute('position', new THREE.BufferAttribute(positions[o], 3));
      mesh.geometry.computeBoundingSphere();
    });
    var triangles = this.geometry.regionTriangles(regions, frame), all = [], colours = [];
    triangles.forEach(function (corners, k) {
      var c = new THREE.Color().setHSL(regionHue(k) / 360, 0.8, 0.48);
      for (var i = 0; i < corners.length; i += 3) { all.push(corners[i], corners[i + 1], corners[i + 2]); colours.push(c.r, c.g, c.b); }
    });
    var g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(all), 3));
    g.setAttribute('color', new THREE.BufferAttribute(new Float32Array(colours), 3));
    this.overlay.geometry.dispose();
    this.overlay.geometry = g;
    if (!this.framed) { this.frameAll(frame); this.framed = true; }
    this.render();
  };
  WebGLView.prototype.look = function (centre, distance) {
    this.controls.target.set(centre[0], centre[1], centre[2]);
    this.camera.position.set(centre[0] + 0.55 * distance, centre[1] + 0.45 * distance, centre[2] + 0.7 * distance);
    this.camera.near = distance / 1000;
    this.camera.far = distance * 100;
    this.camera.updateProjectionMatrix();
    this.controls.update();
    this.render();
  };
  WebGLView.prototype.frameAll = function (frame) {
    var b = this.geometry.bounds(frame);
    this.look(b.centre, 1.3 * b.diagonal);
  };

  /// Without WebGL: an orthographic drawing on a 2D canvas, faces sorted by depth.
  function FlatView(container, geometry) {
    this.canvas = el('canvas');
    this.canvas.width = container.clientWidth || 860;
    this.canvas.height = container.clientHeight || 560;
    container.appendChild(this.canvas);
    this.geometry = geometry;
  }
  FlatView.prototype.show = function (frame, regions) {
    var ctx = this.canvas.getContext('2d'), w = this.canvas.width, h = this.canvas.height;
    var b = this.geometry.bounds(frame), positions = this.geometry.positions(frame);
    // View direction as the 3D view's first camera: from (0.55, 0.45, 0.7).
    var d = [0.55, 0.45, 0.7], n = Math.hypot(d[0], d[1], d[2]);
    d = d.map(function (x) { return x / n; });
    var right = [d[2], 0, -d[0]], rn = Math.hypot(right[0], right[2]);
    right = right.map(function (x) { return x / rn; });
    var up = [d[1] * right[2] - d[2] * right[1], d[2] * right[0] - d[0] * right[2], d[0] * right[1] - d[1] * right[0]];
    var scale = 0.9 * Math.min(w, h) / b.diagonal;
    function project(x, y, z) {
      x -= b.centre[0]; y -= b.centre[1]; z -= b.centre[2];
      return [w / 2 + scale * (x * right[0] + y * right[1] + z * right[2]),
              h / 2 - scale * (x * up[0] + y * up[1] + z * up[2]), x * d[0] + y * d[1] + z * d[2]];
    }
    var faces = [];
    function add(p, q, r, style) {
      var a = project(p[0], p[1], p[2]), bb = project(q[0], q[1], q[2]), c = project(r[0], r[1], r[2]);
      faces.push({ a: a, b: bb, c: c, depth: a[2] + bb[2] + c[2], style: style });
    }
    this.geometry.objects.forEach(function (object, o) {
      var p = positions[o], index = object.index;
      for (var i = 0; i < index.length; i += 3) {
        var v = [index[i], index[i + 1], index[i + 2]].map(function (k) { return [p[3 * k], p[3 * k + 1], p[3 * k + 2]]; });
        add(v[0], v[1], v[2], null);
      }
    });
    this.geometry.regionTriangles(regions, frame).forEach(function (corners, k) {
      for (var i = 0; i < corners.length; i += 9)
        add(corners.slice(i, i + 3), corners.slice(i + 3, i + 6), corners.slice(i + 6, i + 9), regionCss(k));
    });
    faces.sort(function (x, y) { return x.depth - y.depth; });
    ctx.fillStyle = '#fbfbfc';
    ctx.fillRect(0, 0, w, h);
    ctx.lineWidth = 0.5;
    faces.forEach(function (f) {
      ctx.beginPath();
      ctx.moveTo(f.a[0], f.a[1]); ctx.lineTo(f.b[0], f.b[1]); ctx.lineTo(f.c[0], f.c[1]); ctx.closePath();
      ctx.fillStyle = f.style || '#c9ced6';
      ctx.strokeStyle = f.style || '#9aa1ab';
      ctx.fill();
      ctx.stroke();
    });
  };
  FlatView.prototype.frameAll = function () {};
  FlatView.prototype.look = function () {};

  function renderView(report, body, state) {
    body.appendChild(el('h3', { text: '3D view' }));
    var view = report.view;
    if (!view || !view.frames.length) {
      body.appendChild(el('p', { class: 'note', text: 'This page carries no positions: give snag-report the cache ' +
        '(--cache) for a 3D view of the worst frames.' }));
      return null;
    }
    var geometry = new FrameGeometry(view);
    var drawnFaces = 0, totalFaces = 0;
    view.objects.forEach(function (o) { drawnFaces += o.faces_drawn; totalFaces += o.faces_total; });
    var notes = [];
    if (view.decimated) notes.push('Faces away from the regions are sampled to keep the page small: ' +
      fmt(drawnFaces) + ' of ' + fmt(totalFaces) + ' faces drawn; near the regions every face is.');
    if (view.frames.length < view.frames_given) notes.push(fmt(view.frames_given - view.frames.length) +
      ' of the frames given were left out to keep the page small.');
    notes.forEach(function (text) { body.appendChild(el('p', { class: 'note', text: text })); });

    var controls = el('div', { class: 'controls' });
    var info = el('span', { class: 'frame-info' });
    var slider = el('input', { type: 'range', min: 0, max: geometry.frames.length - 1, step: 1, value: 0 });
    var reset = el('button', { type: 'button', text: 'Whole scene' });
    if (geometry.frames.length > 1) controls.appendChild(slider);
    controls.appendChild(info);
    controls.appendChild(reset);
    body.appendChild(controls);
    var wrap = el('div', { class: 'view-wrap' });
    var container = el('div', { class: 'view' });
    var legend = el('div', { class: 'legend' });
    wrap.appendChild(container);
    wrap.appendChild(legend);
    body.appendChild(wrap);

    var drawer = null, webgl = false;
    if (webglAvailable && window.THREE && THREE.OrbitControls) {
      try { drawer = new WebGLView(container, geometry); webgl = true; }
      catch (e) { drawer = null; }
    }
    if (!drawer) {
      body.insertBefore(el('div', { class: 'warning', text: 'WebGL is not available in this browser: the frame is ' +
        'drawn flat from one direction, without orbit controls.' }), controls);
      drawer = new FlatView(container, geometry);
    }

    body.appendChild(el('p', { class: 'note', text: (webgl ? 'Drag to orbit, right-drag to pan, wheel to zoom. ' +
      'Each region of the frame has its own colour; click a region in the list to look at it.' :
      'Each region of the frame has its own colour.') }));
    var result = { webgl: webgl, frame: null, regions: 0, faces: drawnFaces };
    function show(frame) {
      var slot = geometry.frames.map(function (f) { return f.frame; }).indexOf(frame);
      if (slot < 0) {
        info.textContent = 'frame ' + frame + ': its positions are not in this page (frames drawn: ' +
          geometry.frames.map(function (f) { return f.frame; }).join(', ') + ')';
        return;
      }
      slider.value = slot;
      var regions = view.regions.filter(function (r) { return r.frame === frame && r.faces.length; });
      drawer.show(frame, regions);
      var all = view.regions.filter(function (r) { return r.frame === frame; }).length;
      info.textContent = 'frame ' + frame + (geometry.frames.length > 1 ? ' (' + (slot + 1) + ' of ' +
        geometry.frames.length + ' drawn)' : '') + ': ' + regions.length + ' regions coloured' +
        (all > regions.length ? ' (' + (all - regions.length) + ' without face lists)' : '');
      legend.textContent = '';
      regions.forEach(function (r, k) {
        var item = el('div', {}, [el('span', { class: 'swatch', style: 'background:' + regionCss(k) }),
          'region ' + r.id + ' \u00b7 ' + r.kind + ' \u00b7 ' + r.objects + ' \u00b7 ' + fmt(r.face_count) +
          ' faces, ' + fmt(r.events) + ' events \u00b7 track ' + r.track]);
        item.addEventListener('click', function () {
          drawer.look(r.centroid, 0.35 * geometry.bounds(frame).diagonal);
        });
        legend.appendChild(item);
      });
      if (!regions.length) legend.appendChild(el('p', { class: 'note', text: 'No regions in this frame.' }));
      result.frame = frame;
      result.regions = regions.length;
      state.section.setAttribute('data-frame-shown', frame);
      state.section.setAttribute('data-regions-coloured', regions.length);
      var box = container.getBoundingClientRect();
      state.section.setAttribute('data-view-box', [box.left + window.scrollX, box.top + window.scrollY,
        box.right + window.scrollX, box.bottom + window.scrollY].map(Math.round).join(' '));
    }
    slider.addEventListener('input', function () { state.select(geometry.frames[+slider.value].frame); });
    reset.addEventListener('click', function () { drawer.frameAll(result.frame); });
    result.show = show;
    // The worst frame given first is shown first.
    show(view.frames[0].frame);
    return result;
  }

  function renderReport(report, i) {
    var section = document.getElementById('report-' + i);
    var body = section.querySelector('.report-body');
    body.textContent = '';
    var state = { section: section, frame: null, chart: null, view: null, trackRows: null };
    state.markTracks = function () {
      if (!state.trackRows) return;
      Array.prototype.forEach.call(state.trackRows.children, function (tr) {
        var t = state.tracksById[tr.getAttribute('data-track')];
        tr.classList.toggle('active', state.frame !== null && t.first_frame <= state.frame && state.frame <= t.last_frame);
      });
    };
    state.select = function (frame) {
      state.frame = frame;
      if (state.chart) state.chart.draw();
      state.markTracks();
      if (state.view) state.view.show(frame);
    };
    var counts = { frames: 0, tracks: 0, regions: 0, faces: 0, webgl: null };
    try { renderOverview(report, body); } catch (e) { report_error('summary', body, e); }
    try { counts.frames = renderChart(report, body, state); } catch (e) { report_error('chart', body, e); }
    try { counts.tracks = renderTracks(report, body, state); } catch (e) { report_error('tracks', body, e); }
    try {
      state.view = renderView(report, body, state);
      if (state.view) {
        state.frame = state.view.frame;
        if (state.chart) state.chart.draw();
        state.markTracks();
        counts.regions = state.view.regions;
        counts.faces = state.view.faces;
        counts.webgl = state.view.webgl;
      }
    } catch (e) { report_error('3D view', body, e); }
    section.setAttribute('data-frames-charted', counts.frames);
    section.setAttribute('data-tracks-listed', counts.tracks);
    section.setAttribute('data-regions-coloured', counts.regions);
    section.setAttribute('data-faces-drawn', counts.faces);
    if (counts.webgl !== null) section.setAttribute('data-webgl', counts.webgl ? 1 : 0);
    return counts;
  }

  window.addEventListener('error', function (event) {
    document.body.setAttribute('data-error', String(event.message));
  });
  var data = [];
  try {
    data = JSON.parse(document.getElementById('snag-data').textContent);
  } catch (e) { report_error('reading the page data', document.querySelector('main'), e); }
  var sum = { frames: 0, tracks: 0, regions: 0, faces: 0 }, viewsWithout = 0;
  data.forEach(function (report, i) {
    var counts = renderReport(report, i);
    sum.frames += counts.frames;
    sum.tracks += counts.tracks;
    sum.regions += counts.regions;
    sum.faces += counts.faces;
    if (counts.webgl === false) ++viewsWithout;
  });
  var body = document.body;
  body.setAttribute('data-reports', data.length);
  body.setAttribute('data-frames-charted', sum.frames);
  body.setAttribute('data-tracks-listed', sum.tracks);
  body.setAttribute('data-regions-coloured', sum.regions);
  body.setAttribute('data-faces-drawn', sum.faces);
  var first = document.getElementById('report-0');
  if (first && first.hasAttribute('data-frame-shown')) body.setAttribute('data-frame-shown', first.getAttribute('data-frame-shown'));
  body.setAttribute('data-webgl', webglAvailable && !viewsWithout ? 1 : 0);
  if (errors.length) body.setAttribute('data-error', errors.join('; '));
  body.setAttribute('data-ready', 1);
})();
