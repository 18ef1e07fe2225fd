// gridswarm replay page: plays a recorded run back on a canvas.
//
// The data (element #replay-data) is made by orchestrator/src/replay.rs:
// poses are base64 arrays (vertex indices, or 16-bit fixed point for LFP),
// and the per-round series (clock, detected fraction, targets found,
// collisions) are precomputed there. Everything drawn is on canvases, so
// 200 robots over thousands of rounds stay smooth: what only grows (the
// detected area, whole trails) is painted incrementally on off-screen layers
// and repainted from scratch only when the replay goes backwards.
//
// For tests and links: `#round=K&paused=1&speed=S&trails=all|recent|off`
// and `sensing=0|1` (likewise links, detected, grid) set what the controls
// set; #replay-state holds
// JSON `{ready, round, robots_drawn, ..., errors}` after every frame.
(function () {
  "use strict";

  var errors = window.__replayErrors || [];
  var stateEl = document.getElementById("replay-state");
  var D = JSON.parse(document.getElementById("replay-data").textContent);

  // ---------------------------------------------------------------- data
  function decode(b64) {
    var bin = atob(b64), u8 = new Uint8Array(bin.length);
    for (var i = 0; i < bin.length; i++) u8[i] = bin.charCodeAt(i);
    return u8;
  }
  function ints(b64, bits) {
    var u8 = decode(b64);
    return bits === 32 ? new Uint32Array(u8.buffer, 0, u8.length >> 2) : new Uint16Array(u8.buffer, 0, u8.length >> 1);
  }

  var meta = D.meta, P = D.params, bbox = D.bbox;
  var R = meta.rounds;
  var V = D.vertices;
  var lens = D.traj.lens, n = lens.length;
  var T = ints(D.traj.data, D.traj.bits);
  var onGrid = D.traj.mode === "v";
  var qbox = D.traj.box || [0, 0, 1, 1];
  var off = new Array(n);
  (function () { var acc = 0; for (var r = 0; r < n; r++) { off[r] = acc; acc += lens[r]; } })();
  var edges = ints(D.edges.data, D.edges.bits);
  var series = D.series;

  // Pose of robot r at the start of round k (its last pose once its record ends).
  function slot(r, k) { return off[r] + Math.min(k, lens[r] - 1); }
  function poseX(r, k) { var i = slot(r, k); return onGrid ? V[2 * T[i]] : qbox[0] + T[2 * i] * qbox[2]; }
  function poseY(r, k) { var i = slot(r, k); return onGrid ? V[2 * T[i] + 1] : qbox[1] + T[2 * i + 1] * qbox[3]; }

  var failedAt = new Array(n).fill(Infinity);
  for (var fi = 0; fi + 1 < D.failures.length; fi += 2) {
    failedAt[D.failures[fi]] = Math.min(failedAt[D.failures[fi]], D.failures[fi + 1]);
  }
  function byRound(flat, width) {
    var m = {};
    for (var i = 0; i + width - 1 < flat.length; i += width) {
      var k = flat[i];
      (m[k] = m[k] || []).push(flat.slice(i + 1, i + width));
    }
    return m;
  }
  var collisionsAt = byRound(D.collisions, 3);
  // refused is [robot, round, ...]: re-key by round.
  var refusedAt = {};
  for (var ri = 0; ri + 1 < D.refused.length; ri += 2) {
    (refusedAt[D.refused[ri + 1]] = refusedAt[D.refused[ri + 1]] || []).push(D.refused[ri]);
  }
  // Events completed by index k (the round's move has happened).
  function cumulative(map) {
    var c = new Int32Array(R + 2);
    for (var k = 0; k <= R; k++) c[k + 1] = c[k] + (map[k] ? map[k].length : 0);
    return c;
  }
  var cumRefused = cumulative(refusedAt);
  // The engine's count of every round when rounds.csv has it: it includes
  // collisions the poses cannot show (robots that back off end where they
  // started); the marks are those the poses show.
  var counts = D.collision_counts;
  function collisionsIn(k) {
    return counts ? counts[k] || 0 : collisionsAt[k] ? collisionsAt[k].length : 0;
  }
  var cumCollisions = new Int32Array(R + 2);
  for (var ck = 0; ck <= R; ck++) cumCollisions[ck + 1] = cumCollisions[ck] + collisionsIn(ck);

  // The same palette as routes.svg (palette.rs): never the targets' red;
  // robots past its end trail dashed, as their routes are.
  var PALETTE = D.palette, DASHES = [[8, 4], [2, 3], [12, 3, 2, 3]];
  var colours = [], dashes = [];
  for (var ci = 0; ci < n; ci++) {
    var lap = Math.floor(ci / PALETTE.length);
    colours.push(PALETTE[ci % PALETTE.length]);
    dashes.push(lap === 0 ? [] : DASHES[(lap - 1) % DASHES.length]);
  }
  // Injected faults: crashed from their round on, frozen until the thaw.
  var crashedAt = new Array(n).fill(Infinity), frozen = [];
  D.faults.forEach(function (f) {
    if (f[1] === 0) crashedAt[f[0]] = Math.min(crashedAt[f[0]], f[2]);
    else frozen.push([f[0], f[2], f[3] < 0 ? Infinity : f[3]]);
  });
  function isFrozen(r, k) {
    return frozen.some(function (f) { return f[0] === r && f[1] <= k && k < f[2]; });
  }
  // What a robot is at round k: crashed, frozen, declared failed by the
  // others, its record ended (stopped), or searching.
  function stateOf(r, k) {
    if (crashedAt[r] <= k) return "crashed";
    if (isFrozen(r, k)) return "frozen";
    if (failedAt[r] <= k) return "failed";
    return k >= lens[r] ? "ended" : "active";
  }

  var C = {
    area: "#fbfbf8", outline: "#33363a", edge: "#d3d7dc", vertex: "#b4bac1",
    obstacle: "#8e949b", obstacleEdge: "#5b6067", detected: "#8fc0ea",
    target: D.target_colour, found: D.target_colour, link: "rgba(16,60,110,0.75)",
    collision: "#e0001b", refused: "#ff8c00", failed: "#9a9a9a"
  };

  // ------------------------------------------------------------- controls
  var $ = function (id) { return document.getElementById(id); };
  var stage = $("stage"), view = $("view"), ctx = view.getContext("2d");
  var chart = $("chart"), cctx = chart.getContext("2d");
  var slider = $("slider"), playBtn = $("play"), speedSel = $("speed");
  var opt = { detected: true, grid: true, links: true, sensing: true, trails: n <= 12 ? "all" : "recent" };
  $("opt-trails").value = opt.trails;

  var SPEEDS = [0.25, 0.5, 1, 2, 4, 8, 16, 32, 64, 128, 256];
  SPEEDS.forEach(function (v) {
    var o = document.createElement("option");
    o.value = String(v);
    o.textContent = v + " rounds/s";
    speedSel.appendChild(o);
  });
  // About forty seconds for the whole run by default.
  var speed = SPEEDS.filter(function (v) { return v >= Math.min(64, Math.max(1, R / 40)); })[0] || 64;
  speedSel.value = String(speed);

  var u = 0, playing = true, dirty = true;
  slider.max = String(R);

  // ----------------------------------------------------------- geometry
  var W = 0, H = 0, dpr = 1, s = 1, ox = 0, oy = 0;
  function X(x) { return ox + (x - bbox[0]) * s; }
  function Y(y) { return oy + (bbox[3] - y) * s; }

  function layer() {
    var c = document.createElement("canvas");
    c.width = Math.max(1, Math.round(W * dpr));
    c.height = Math.max(1, Math.round(H * dpr));
    var g = c.getContext("2d");
    g.setTransform(dpr, 0, 0, dpr, 0, 0);
    return { canvas: c, g: g };
  }
  function polyPath(g, flat) {
    g.moveTo(X(flat[0]), Y(flat[1]));
    for (var i = 2; i + 1 < flat.length; i += 2) g.lineTo(X(flat[i]), Y(flat[i + 1]));
    g.closePath();
  }
  function areaPath(g) { g.beginPath(); polyPath(g, D.area); }

  var base, top, cover, trails;
  var coverK = -1, coverSeen = null, trailK = -1;

  function stageSize() {
    var rect = stage.getBoundingClientRect();
    return [Math.max(120, Math.round(rect.width)), Math.max(120, Math.round(rect.height)), window.devicePixelRatio || 1];
  }
  function resized() {
    var z = stageSize();
    return z[0] !== W || z[1] !== H || z[2] !== dpr;
  }

  function layout() {
    var z = stageSize();
    W = z[0];
    H = z[1];
    dpr = z[2];
    view.width = Math.round(W * dpr);
    view.height = Math.round(H * dpr);
    var bw = Math.max(1e-9, bbox[2] - bbox[0]), bh = Math.max(1e-9, bbox[3] - bbox[1]), m = 18;
    s = Math.max(1e-6, Math.min((W - 2 * m) / bw, (H - 2 * m) / bh));
    ox = (W - bw * s) / 2;
    oy = (H - bh * s) / 2;
    base = layer();
    areaPath(base.g);
    base.g.fillStyle = C.area;
    base.g.fill();
    buildTop();
    cover = layer();
    coverK = -1;
    trails = layer();
    trailK = -1;
    layoutChart();
    dirty = true;
  }

  function buildTop() {
    top = layer();
    var g = top.g, a = P.a;
    if (opt.grid) {
      g.beginPath();
      for (var e = 0; e + 1 < edges.length; e += 2) {
        var p = edges[e], q = edges[e + 1];
        g.moveTo(X(V[2 * p]), Y(V[2 * p + 1]));
        g.lineTo(X(V[2 * q]), Y(V[2 * q + 1]));
      }
      g.strokeStyle = C.edge;
      g.lineWidth = Math.min(1, Math.max(0.4, 0.02 * a * s));
      g.stroke();
      var dot = Math.min(2.2, Math.max(0.7, 0.05 * a * s));
      g.fillStyle = C.vertex;
      g.beginPath();
      for (var v = 0; v < D.accessible; v++) {
        var x = X(V[2 * v]), y = Y(V[2 * v + 1]);
        g.moveTo(x + dot, y);
        g.arc(x, y, dot, 0, 2 * Math.PI);
      }
      g.fill();
    }
    D.obstacles.forEach(function (o) {
      g.beginPath();
      if (o.poly) polyPath(g, o.poly);
      else g.arc(X(o.circle[0]), Y(o.circle[1]), o.circle[2] * s, 0, 2 * Math.PI);
      g.fillStyle = C.obstacle;
      g.fill();
      g.strokeStyle = C.obstacleEdge;
      g.lineWidth = 1;
      g.stroke();
    });
    areaPath(g);
    g.strokeStyle = C.outline;
    g.lineWidth = 1.6;
    g.stroke();
  }

  // Detected area: a disc of r_st around every place a robot has stood,
  // painted once per place (vertex, or LFP cell of a/10).
  function advanceCover(k) {
    if (k < coverK) { cover = layer(); coverK = -1; }
    if (coverK < 0) coverSeen = onGrid ? new Uint8Array(V.length / 2) : new Set();
    var g = cover.g, rad = P.r_st * s, count = 0, cell = P.a / 10;
    g.fillStyle = C.detected;
    g.beginPath();
    for (var j = coverK + 1; j <= k; j++) {
      for (var r = 0; r < n; r++) {
        if (j >= lens[r]) continue;
        var i = off[r] + j, x, y;
        if (onGrid) {
          if (coverSeen[T[i]]) continue;
          coverSeen[T[i]] = 1;
          x = V[2 * T[i]];
          y = V[2 * T[i] + 1];
        } else {
          x = qbox[0] + T[2 * i] * qbox[2];
          y = qbox[1] + T[2 * i + 1] * qbox[3];
          var key = Math.round(x / cell) + "," + Math.round(y / cell);
          if (coverSeen.has(key)) continue;
          coverSeen.add(key);
        }
        g.moveTo(X(x) + rad, Y(y));
        g.arc(X(x), Y(y), rad, 0, 2 * Math.PI);
        // Keep paths short: filling one path of many thousand arcs is slow.
        if (++count % 1000 === 0) { g.fill(); g.beginPath(); }
      }
    }
    g.fill();
    coverK = Math.max(coverK, k);
  }

  function trailWidth() { return Math.min(3, Math.max(1, 0.06 * P.a * s)); }

  // Whole routes up to pose k, painted opaque (the layer is shown translucent).
  function advanceTrails(k) {
    if (k < trailK) { trails = layer(); trailK = -1; }
    var g = trails.g;
    g.lineWidth = trailWidth();
    g.lineJoin = "round";
    g.lineCap = "round";
    var from = Math.max(0, trailK);
    for (var r = 0; r < n; r++) {
      var end = Math.min(k, lens[r] - 1);
      if (end <= from) continue;
      g.beginPath();
      g.moveTo(X(poseX(r, from)), Y(poseY(r, from)));
      for (var j = from + 1; j <= end; j++) g.lineTo(X(poseX(r, j)), Y(poseY(r, j)));
      g.strokeStyle = colours[r];
      g.setLineDash(dashes[r]);
      g.stroke();
    }
    g.setLineDash([]);
    trailK = Math.max(trailK, k);
  }

  // ------------------------------------------------------------- drawing
  function diamond(g, x, y, h) {
    g.beginPath();
    g.moveTo(x, y - h);
    g.lineTo(x + h, y);
    g.lineTo(x, y + h);
    g.lineTo(x - h, y);
    g.closePath();
  }
  // Targets in the targets' colour only, which no robot has: hollow until
  // found, then filled.
  function drawTarget(g, x, y, found, h) {
    diamond(g, x, y, h);
    g.fillStyle = found ? C.found : "#ffffff";
    g.fill();
    g.lineWidth = 2;
    g.strokeStyle = found ? "#6b0f10" : C.target;
    g.stroke();
  }
  function robotRadius() { return Math.max(3.5, P.r_rob * s); }
  // The marks match routes.svg's end marks: a black cross on the robot's
  // colour when crashed, white pause bars when frozen, a white disc when
  // its record ended; grey with a cross when the others declared it failed.
  function drawRobot(g, x, y, rr, colour, state, label) {
    var failed = state === "failed", ended = state === "ended";
    g.beginPath();
    g.arc(x, y, rr, 0, 2 * Math.PI);
    g.fillStyle = failed ? C.failed : ended ? "#ffffff" : colour;
    g.fill();
    g.lineWidth = Math.max(1, rr * 0.18);
    g.strokeStyle = failed || state === "frozen" ? "#222" : ended ? colour : "rgba(0,0,0,0.65)";
    g.stroke();
    if (failed || state === "crashed") {
      var c = rr * (failed ? 0.9 : 1.25);
      g.beginPath();
      g.moveTo(x - c, y - c); g.lineTo(x + c, y + c);
      g.moveTo(x + c, y - c); g.lineTo(x - c, y + c);
      g.lineWidth = Math.max(1.5, rr * 0.34);
      g.strokeStyle = "#111";
      g.lineCap = "round";
      g.stroke();
      g.lineCap = "butt";
    } else if (state === "frozen") {
      var w = rr * 0.32, h = rr * 1.1;
      g.fillStyle = "#ffffff";
      g.fillRect(x - 1.1 * w - w / 2, y - h / 2, w, h);
      g.fillRect(x + 1.1 * w - w / 2, y - h / 2, w, h);
    } else if (label && rr >= 8) {
      g.fillStyle = ended ? colour : "#ffffff";
      g.font = "600 " + Math.round(rr * 1.05) + "px system-ui, sans-serif";
      g.textAlign = "center";
      g.textBaseline = "middle";
      g.fillText(label, x, y + 0.5);
    }
  }
  function ring(g, x, y, rad, colour, alpha, width) {
    g.globalAlpha = alpha;
    g.beginPath();
    g.arc(x, y, rad, 0, 2 * Math.PI);
    g.strokeStyle = colour;
    g.lineWidth = width;
    g.stroke();
    g.globalAlpha = 1;
  }
  function cross(g, x, y, c, colour, alpha) {
    g.globalAlpha = alpha;
    g.beginPath();
    g.moveTo(x - c, y - c); g.lineTo(x + c, y + c);
    g.moveTo(x + c, y - c); g.lineTo(x - c, y + c);
    g.strokeStyle = colour;
    g.lineWidth = 3;
    g.stroke();
    g.globalAlpha = 1;
  }

  // Position of robot r at fractional round t (straight moves, as step 6).
  function at(r, t) {
    var k = Math.floor(t), f = t - k;
    if (failedAt[r] <= k || crashedAt[r] <= k || k + 1 >= lens[r] || f === 0) return [poseX(r, k), poseY(r, k)];
    var x0 = poseX(r, k), y0 = poseY(r, k);
    return [x0 + (poseX(r, k + 1) - x0) * f, y0 + (poseY(r, k + 1) - y0) * f];
  }

  var last = {};
  function draw() {
    // The window may have settled its size after the first layout (a
    // headless browser does): never stretch a canvas drawn for another size.
    if (resized()) layout();
    dirty = false;
    var k = Math.min(R, Math.floor(u)), f = k >= R ? 0 : u - k;
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.clearRect(0, 0, W, H);
    ctx.drawImage(base.canvas, 0, 0, W, H);
    if (opt.detected) {
      advanceCover(k);
      ctx.save();
      areaPath(ctx);
      ctx.clip();
      ctx.globalAlpha = 0.55;
      ctx.drawImage(cover.canvas, 0, 0, W, H);
      ctx.restore();
    }
    ctx.drawImage(top.canvas, 0, 0, W, H);

    // Targets: sensing circles, then the marks.
    var th = Math.min(9, Math.max(4, 0.16 * P.a * s)), found = 0, circles = 0;
    for (var t = 0; t + 1 < D.targets.length; t += 2) {
      var tx = X(D.targets[t]), ty = Y(D.targets[t + 1]), fa = D.target_found_at[t / 2];
      var isFound = fa !== null && fa <= k;
      if (isFound) found++;
      if (opt.sensing) {
        circles++;
        ctx.beginPath();
        ctx.arc(tx, ty, P.r_st * s, 0, 2 * Math.PI);
        ctx.setLineDash([4, 3]);
        ctx.strokeStyle = isFound ? "rgba(44,160,44,0.55)" : "rgba(214,39,40,0.45)";
        ctx.lineWidth = 1;
        ctx.stroke();
        ctx.setLineDash([]);
      }
      drawTarget(ctx, tx, ty, isFound, th);
    }

    var pos = new Array(n);
    for (var r = 0; r < n; r++) pos[r] = at(r, u);

    // Trails.
    if (opt.trails === "all") {
      advanceTrails(k);
      ctx.globalAlpha = 0.6;
      ctx.drawImage(trails.canvas, 0, 0, W, H);
      ctx.globalAlpha = 1;
    }
    if (opt.trails !== "off") {
      ctx.lineWidth = trailWidth();
      ctx.lineJoin = "round";
      ctx.lineCap = "round";
      ctx.globalAlpha = 0.6;
      for (r = 0; r < n; r++) {
        var from = opt.trails === "all" ? Math.min(k, lens[r] - 1) : Math.max(0, k - 20);
        ctx.beginPath();
        ctx.moveTo(X(poseX(r, from)), Y(poseY(r, from)));
        for (var j = from + 1; j <= k && j < lens[r]; j++) ctx.lineTo(X(poseX(r, j)), Y(poseY(r, j)));
        ctx.lineTo(X(pos[r][0]), Y(pos[r][1]));
        ctx.strokeStyle = colours[r];
        ctx.setLineDash(dashes[r]);
        ctx.stroke();
      }
      ctx.setLineDash([]);
      ctx.globalAlpha = 1;
    }

    // Radio links of the round: robots within r_c at its start.
    var active = [];
    for (r = 0; r < n; r++) if (stateOf(r, k) === "active") active.push(r);
    if (opt.links) {
      var rc2 = P.r_c * P.r_c;
      ctx.beginPath();
      for (var a = 0; a < active.length; a++) {
        var i = active[a], xi = poseX(i, k), yi = poseY(i, k);
        for (var b = a + 1; b < active.length; b++) {
          var jj = active[b], dx = poseX(jj, k) - xi, dy = poseY(jj, k) - yi;
          if (dx * dx + dy * dy <= rc2) {
            ctx.moveTo(X(pos[i][0]), Y(pos[i][1]));
            ctx.lineTo(X(pos[jj][0]), Y(pos[jj][1]));
          }
        }
      }
      ctx.strokeStyle = C.link;
      ctx.lineWidth = 1.5;
      ctx.setLineDash([4, 3]);
      ctx.stroke();
      ctx.setLineDash([]);
    }

    var rr = robotRadius();
    // Collisions: while the round's move is under way, and fading for two rounds after.
    for (var e = Math.max(0, k - 2); e <= k; e++) {
      var evs = collisionsAt[e];
      if (!evs || u <= e) continue;
      var age = u - (e + 1), alpha = age <= 0 ? 1 : Math.max(0, 1 - age / 2);
      if (alpha <= 0) continue;
      evs.forEach(function (ev) {
        var p = at(ev[0], Math.min(u, e + 1)), q = at(ev[1], Math.min(u, e + 1));
        var mx = X((p[0] + q[0]) / 2), my = Y((p[1] + q[1]) / 2);
        ring(ctx, mx, my, Math.max(rr * 1.7, 2 * P.r_safe * s), C.collision, alpha, 2.5);
        ctx.globalAlpha = alpha;
        ctx.beginPath();
        ctx.moveTo(X(p[0]), Y(p[1]));
        ctx.lineTo(X(q[0]), Y(q[1]));
        ctx.strokeStyle = C.collision;
        ctx.lineWidth = 2;
        ctx.stroke();
        ctx.globalAlpha = 1;
      });
    }
    // Refused moves: the robot stays; marked during the round and the next.
    for (e = Math.max(0, k - 1); e <= k; e++) {
      var rs = refusedAt[e];
      if (!rs || u < e) continue;
      var al = u <= e + 1 ? 1 : Math.max(0, 1 - (u - e - 1));
      rs.forEach(function (robot) {
        var p = pos[robot];
        ring(ctx, X(p[0]), Y(p[1]), rr * 1.9, C.refused, al, 2.5);
        cross(ctx, X(p[0]) + rr * 1.6, Y(p[1]) - rr * 1.6, Math.max(3, rr * 0.5), C.refused, al);
      });
    }

    // Robots last, on top of everything.
    var drawn = 0, failedDrawn = 0, states = { crashed: 0, frozen: 0, failed: 0, ended: 0, active: 0 };
    for (r = 0; r < n; r++) {
      var state = stateOf(r, k);
      drawRobot(ctx, X(pos[r][0]), Y(pos[r][1]), rr, colours[r], state, n <= 100 ? String(r) : "");
      drawn++;
      states[state]++;
      if (failedAt[r] <= k) failedDrawn++;
    }

    // Readout.
    var t0 = series.time_s[k], t1 = series.time_s[Math.min(R, k + 1)];
    var time = t0 + (t1 - t0) * f;
    var collisionsSoFar = cumCollisions[k] + (f > 0 ? collisionsIn(k) : 0);
    var refusedSoFar = cumRefused[k] + (f > 0 && refusedAt[k] ? refusedAt[k].length : 0);
    var det = series.detected[k];
    setText("r-round", k + " / " + R);
    setText("r-time", (series.time_exact ? "" : "~") + time.toFixed(1) + " s");
    setText("r-targets", series.found[k] + " / " + meta.targets_total);
    setText("r-detected", (100 * det).toFixed(1) + " %");
    setText("r-robots", active.length + " / " + n);
    setText("r-collisions", String(collisionsSoFar));
    setText("r-refused", D.refused.length ? String(refusedSoFar) : D.refused_total != null ? D.refused_total + " (total)" : "0");
    setText("r-failed", String(failedDrawn));
    setText("r-crashed", String(states.crashed));
    setText("r-frozen", String(states.frozen));
    setText("roundlabel", "round " + k + " of " + R);
    if (String(k) !== slider.value) slider.value = String(k);
    drawChart();

    publish({
      ready: true, round: k, u: Math.round(u * 1000) / 1000, rounds: R, robots: n,
      robots_drawn: drawn, robots_active: active.length, robots_failed: failedDrawn, sensing_circles: circles,
      robots_crashed: states.crashed, robots_frozen: states.frozen, robots_ended: states.ended,
      robot_colours: colours.slice(0, 30), settings: D.settings,
      targets_found: series.found[k], targets_marked_found: found, detected: det,
      time_s: Math.round(time * 1000) / 1000, collisions: collisionsSoFar, playing: playing,
      canvas: [view.width, view.height], errors: errors.slice()
    });
  }

  function setText(id, text) {
    if (last[id] !== text) { $(id).textContent = text; last[id] = text; }
  }
  function publish(state) { stateEl.textContent = JSON.stringify(state); }

  // ---------------------------------------------------------------- chart
  var chartBase = null, cw = 0, chh = 0;
  function layoutChart() {
    var rect = chart.getBoundingClientRect();
    cw = Math.max(60, Math.round(rect.width));
    chh = Math.max(40, Math.round(rect.height));
    chart.width = Math.round(cw * dpr);
    chart.height = Math.round(chh * dpr);
    var c = document.createElement("canvas");
    c.width = chart.width;
    c.height = chart.height;
    var g = c.getContext("2d");
    g.setTransform(dpr, 0, 0, dpr, 0, 0);
    // Room on the left for the fraction's numbers, below for the rounds'.
    var pad = 4, padL = 30, padB = 14, w = cw - padL - pad, h = chh - pad - padB;
    var cx = function (k) { return padL + (R > 0 ? k / R : 0) * w; };
    var cy = function (v) { return pad + (1 - v) * h; };
    g.strokeStyle = "#eee";
    g.lineWidth = 1;
    [0.25, 0.5, 0.75].forEach(function (v) { g.beginPath(); g.moveTo(padL, cy(v)); g.lineTo(padL + w, cy(v)); g.stroke(); });
    g.fillStyle = "#666";
    g.font = "10px system-ui, sans-serif";
    g.textAlign = "right";
    g.textBaseline = "middle";
    [0, 0.5, 1].forEach(function (v) { g.fillText(Math.round(100 * v) + "%", padL - 3, cy(v)); });
    g.textBaseline = "top";
    g.textAlign = "left";
    g.fillText("round 0", padL, pad + h + 2);
    g.textAlign = "right";
    g.fillText(String(R), padL + w, pad + h + 2);
    // Detected fraction, filled.
    var step = Math.max(1, Math.floor(R / (2 * w)));
    g.beginPath();
    g.moveTo(cx(0), cy(0));
    for (var k = 0; k <= R; k += step) g.lineTo(cx(k), cy(series.detected[k]));
    g.lineTo(cx(R), cy(series.detected[R]));
    g.lineTo(cx(R), cy(0));
    g.closePath();
    g.fillStyle = "rgba(31,119,180,0.15)";
    g.fill();
    g.beginPath();
    for (k = 0; k <= R; k += step) g.lineTo(cx(k), cy(series.detected[k]));
    g.lineTo(cx(R), cy(series.detected[R]));
    g.strokeStyle = "#1f77b4";
    g.lineWidth = 1.5;
    g.stroke();
    // Targets found, as a step line.
    var tot = Math.max(1, meta.targets_total);
    g.beginPath();
    g.moveTo(cx(0), cy(series.found[0] / tot));
    for (k = 1; k <= R; k++) {
      if (series.found[k] !== series.found[k - 1]) {
        g.lineTo(cx(k), cy(series.found[k - 1] / tot));
        g.lineTo(cx(k), cy(series.found[k] / tot));
      }
    }
    g.lineTo(cx(R), cy(series.found[R] / tot));
    g.strokeStyle = "#2ca02c";
    g.lineWidth = 1.5;
    g.stroke();
    chartBase = { canvas: c, x: cx };
  }
  function drawChart() {
    cctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    cctx.clearRect(0, 0, cw, chh);
    cctx.drawImage(chartBase.canvas, 0, 0, cw, chh);
    var x = chartBase.x(Math.min(u, R));
    cctx.beginPath();
    cctx.moveTo(x, 0);
    cctx.lineTo(x, chh);
    cctx.strokeStyle = "rgba(0,0,0,0.55)";
    cctx.lineWidth = 1;
    cctx.stroke();
  }

  // ------------------------------------------------------- static panels
  function legend() {
    var items = [
      ["robot (number = its id, as in the CLI and JSON)", function (g) { drawRobot(g, 11, 9, 6, colours[0], "active", ""); }],
      ["crashed robot", function (g) { drawRobot(g, 11, 9, 6, colours[0], "crashed", ""); }],
      ["frozen robot", function (g) { drawRobot(g, 11, 9, 6, colours[0], "frozen", ""); }],
      ["stopped: its record ended", function (g) { drawRobot(g, 11, 9, 6, colours[0], "ended", ""); }],
      ["declared failed by the others", function (g) { drawRobot(g, 11, 9, 6, "", "failed", ""); }],
      ["target / found", function (g) { drawTarget(g, 6, 9, false, 5); drawTarget(g, 17, 9, true, 5); }],
      ["detected area", function (g) { g.fillStyle = C.detected; g.globalAlpha = 0.55; g.fillRect(2, 3, 18, 12); g.globalAlpha = 1; }],
      ["radio link (within r_c)", function (g) { g.strokeStyle = C.link; g.lineWidth = 1.5; g.setLineDash([4, 3]); g.beginPath(); g.moveTo(2, 13); g.lineTo(20, 5); g.stroke(); g.setLineDash([]); }],
      ["trail", function (g) { g.strokeStyle = colours[0]; g.globalAlpha = 0.6; g.lineWidth = 2.5; g.beginPath(); g.moveTo(2, 14); g.lineTo(9, 5); g.lineTo(20, 10); g.stroke(); g.globalAlpha = 1; }],
      ["collision (closer than 2 r_safe)", function (g) { ring(g, 11, 9, 7, C.collision, 1, 2.5); }],
      ["refused move", function (g) { ring(g, 9, 10, 6, C.refused, 1, 2); cross(g, 16, 4, 3, C.refused, 1); }],
      ["obstacle", function (g) { g.fillStyle = C.obstacle; g.strokeStyle = C.obstacleEdge; g.fillRect(3, 3, 16, 12); g.strokeRect(3, 3, 16, 12); }]
    ];
    var ul = $("legend");
    items.forEach(function (it) {
      var li = document.createElement("li"), c = document.createElement("canvas");
      c.width = 22 * dpr; c.height = 18 * dpr;
      c.style.width = "22px"; c.style.height = "18px";
      var g = c.getContext("2d");
      g.setTransform(dpr, 0, 0, dpr, 0, 0);
      it[1](g);
      li.appendChild(c);
      li.appendChild(document.createTextNode(it[0]));
      ul.appendChild(li);
    });
  }

  function runInfo() {
    var given = D.settings.faults;
    var rows = [
      ["faults", given.length ? given.join(", ") : "none"], ["radio", D.settings.radio],
      ["grid side a", P.a + " m"], ["r_rob / r_safe", P.r_rob + " / " + P.r_safe + " m"],
      ["r_st (targets)", P.r_st + " m"], ["r_c (radio)", P.r_c + " m"],
      ["rounds", String(R)],
      ["search time", meta.search_time_s != null ? Number(meta.search_time_s).toFixed(1) + " s" : "-"],
      ["final coverage", meta.coverage != null ? (100 * meta.coverage).toFixed(2) + " %" : "-"],
      ["collisions (engine)", meta.collisions != null ? String(meta.collisions) : "-"],
      ["clock", series.time_exact ? "engine, per round" : "total spread evenly"]
    ];
    var tb = $("runinfo");
    rows.forEach(function (row) {
      var tr = document.createElement("tr");
      row.forEach(function (cell) { var td = document.createElement("td"); td.textContent = cell; tr.appendChild(td); });
      tb.appendChild(tr);
    });
  }

  // -------------------------------------------------------------- events
  function setPlaying(p) {
    playing = p && R > 0;
    playBtn.textContent = playing ? "Pause" : "Play";
    dirty = true;
  }
  function seek(v) { u = Math.max(0, Math.min(R, v)); dirty = true; }

  playBtn.addEventListener("click", function () {
    if (!playing && u >= R) u = 0;
    setPlaying(!playing);
  });
  $("back").addEventListener("click", function () { setPlaying(false); seek(Math.ceil(u) - 1); });
  $("fwd").addEventListener("click", function () { setPlaying(false); seek(Math.floor(u) + 1); });
  slider.addEventListener("input", function () { setPlaying(false); seek(Number(slider.value)); });
  speedSel.addEventListener("change", function () { speed = Number(speedSel.value) || 1; });
  ["detected", "links", "sensing"].forEach(function (name) {
    $("opt-" + name).addEventListener("change", function (ev) { opt[name] = ev.target.checked; dirty = true; });
  });
  $("opt-grid").addEventListener("change", function (ev) { opt.grid = ev.target.checked; buildTop(); dirty = true; });
  $("opt-trails").addEventListener("change", function (ev) { opt.trails = ev.target.value; dirty = true; });
  document.addEventListener("keydown", function (ev) {
    if (ev.target && (ev.target.tagName === "SELECT" || ev.target.tagName === "INPUT") && ev.key !== " ") return;
    if (ev.key === " ") { ev.preventDefault(); playBtn.click(); }
    else if (ev.key === "ArrowLeft") $("back").click();
    else if (ev.key === "ArrowRight") $("fwd").click();
    else if (ev.key === "Home") { setPlaying(false); seek(0); }
    else if (ev.key === "End") { setPlaying(false); seek(R); }
  });
  function onResize() { if (resized()) { layout(); draw(); } }
  window.addEventListener("resize", onResize);
  // Called after layout and before paint, so no frame shows a stretched canvas.
  if (window.ResizeObserver) new ResizeObserver(onResize).observe(stage);

  // `#round=K&paused=1&speed=S&trails=all|recent|off`
  function readHash() {
    var h = (location.hash || "").replace(/^#/, ""), q = {};
    h.split("&").forEach(function (kv) {
      var p = kv.split("=");
      if (p[0]) q[decodeURIComponent(p[0])] = decodeURIComponent(p[1] || "");
    });
    // A fractional round shows the moves under way (e.g. round=12.5).
    if (q.round !== undefined && q.round !== "" && !isNaN(Number(q.round))) seek(Number(q.round));
    if (q.speed && Number(q.speed) > 0) { speed = Number(q.speed); speedSel.value = String(speed); }
    if (q.trails === "all" || q.trails === "recent" || q.trails === "off") {
      opt.trails = q.trails;
      $("opt-trails").value = q.trails;
    }
    // The same path as a click on the box, so a test can check both.
    [["sensing", "opt-sensing"], ["links", "opt-links"], ["detected", "opt-detected"], ["grid", "opt-grid"]].forEach(function (o) {
      if (q[o[0]] !== "0" && q[o[0]] !== "1") return;
      var box = $(o[1]);
      box.checked = q[o[0]] === "1";
      box.dispatchEvent(new Event("change"));
    });
    setPlaying(!(q.paused === "1" || q.paused === "true"));
  }
  window.addEventListener("hashchange", function () { readHash(); draw(); });

  var lastTs = null;
  function tick(ts) {
    if (playing) {
      if (lastTs !== null) {
        seek(u + Math.min(0.25, (ts - lastTs) / 1000) * speed);
        if (u >= R) setPlaying(false);
      }
      lastTs = ts;
    } else {
      lastTs = null;
    }
    if (dirty) draw();
    window.requestAnimationFrame(tick);
  }

  // ---------------------------------------------------------------- start
  var m = meta;
  $("title").textContent = D.title;
  $("subtitle").textContent = [
    "scenario " + m.scenario, m.grid + " grid", m.algorithm + (m.label ? " " + m.label : ""),
    n + " robots", "seed " + m.seed, "situation " + m.situation,
    m.complete === true ? "complete" : m.complete === false ? "INCOMPLETE (round limit)" : ""
  ].filter(Boolean).join("  \u00b7  ");
  layout();
  legend();
  runInfo();
  readHash();
  // Drawn now, not on the first animation frame, so that a page loaded
  // without animation (a headless dump) already shows the state.
  draw();
  window.requestAnimationFrame(tick);
})();
