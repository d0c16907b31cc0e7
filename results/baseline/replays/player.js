// magbench replay player: draws the run in #replay-data on an SVG and plays it.
// The page's time is in the URL: #t=3.2 (also speed=2, tree=1, play=1).
(function () {
  "use strict";
  // the page's bulk numbers are packed (harness/src/replay/pack.rs): base64 of raw deflate of
  // zig-zag varint columns; unpack rebuilds the arrays the player draws from
  function unpack(P) {
    var bin = atob(P.packed), bytes = new Uint8Array(bin.length);
    for (var i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    var stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("deflate-raw"));
    return new Response(stream).arrayBuffer().then(function (buf) {
      var b = new Uint8Array(buf), at = 0;
      function num() {
        var u = 0, m = 1, c;
        do { c = b[at++]; u += (c & 127) * m; m *= 128; } while (c & 128);
        return u % 2 ? -(u + 1) / 2 : u / 2;
      }
      function col(delta) {
        var n = num(), out = new Array(n), acc = 0;
        for (var k = 0; k < n; k++) { var v = num(); acc = delta ? acc + v : v; out[k] = acc; }
        return out;
      }
      function pairs(xs, ys) {
        var out = new Array(2 * xs.length);
        for (var k = 0; k < xs.length; k++) { out[2 * k] = xs[k]; out[2 * k + 1] = ys[k]; }
        return out;
      }
      var D = P, a, k;
      D.t = col(true).map(function (ms) { return ms / 1000; });
      D.leg = col(true);
      D.plan = col(true);
      D.truth = [];
      for (a = 0; a < P.scene.agents; a++) D.truth.push(pairs(col(true), col(true)));
      D.obs = [];
      var observed = num();
      for (a = 0; a < observed; a++) {
        var seen = col(false), dx = col(false), dy = col(false), o = [], j = 0, tr = D.truth[a];
        for (k = 0; k < seen.length; k++) {
          if (seen[k]) { o.push(tr[2 * k] + dx[j], tr[2 * k + 1] + dy[j]); j++; }
          else o.push(null, null);
        }
        D.obs.push(o);
      }
      var f = [col(true), col(true), col(true), col(true)];
      D.field = f[0].map(function (_, k) {
        return [f[0][k] / 10, f[1][k] / 10, f[2][k] / 10, f[3][k] / 10];
      });
      D.plans.forEach(function (p) {
        p.paths = [];
        for (var n = num(); n > 0; n--) p.paths.push(pairs(col(true), col(true)));
      });
      D.trees.forEach(function (t) {
        var x = col(true), y = col(false), dx = col(false), dy = col(false), e = [];
        for (var k = 0; k < x.length; k++) e.push(x[k], y[k], x[k] + dx[k], y[k] + dy[k]);
        t.edges = e;
      });
      return D;
    });
  }

  var packed = JSON.parse(document.getElementById("replay-data").textContent);
  (typeof DecompressionStream === "function" ? unpack(packed) : Promise.reject(
    new Error("this browser has no DecompressionStream (Chromium 103, Firefox 113, Safari 16.4 or later)")
  )).then(play, function (e) {
    document.getElementById("frame-info").textContent = "The replay's data could not be read: " + e.message;
  });

  function play(D) {
    var NS = "http://www.w3.org/2000/svg";
    var S = D.scale, TS = D.tree_scale, A = D.scene.agents, N = D.t.length;
    var T = N ? D.t[N - 1] : 0;
    var svg = document.getElementById("view");
    var $ = function (id) { return document.getElementById(id); };
    var colors = D.colors;
    var col = function (i) { return colors[i % colors.length]; };

    function el(tag, attrs, parent) {
      var e = document.createElementNS(NS, tag);
      for (var k in attrs) e.setAttribute(k, attrs[k]);
      if (parent) parent.appendChild(e);
      return e;
    }
    function f2(x) { return (Math.round(x * 100) / 100).toString(); }

    // the view box covers every leg's world plus a margin; y points up
    var W = 0, H = 0;
    D.scene.legs.forEach(function (l) { W = Math.max(W, l.w); H = Math.max(H, l.h); });
    var M = 1;
    svg.setAttribute("viewBox", (-M) + " " + (-M) + " " + (W + 2 * M) + " " + (H + 2 * M));
    var root = el("g", { transform: "translate(0," + H + ") scale(1,-1)" }, svg);
    var layers = {};
    ["map", "tree", "goals", "plans", "trails", "events", "agents", "obs", "field"].forEach(
      function (n) { layers[n] = el("g", { id: "layer-" + n }, root); });

    function clear(g) { while (g.firstChild) g.removeChild(g.firstChild); }
    function pts(flat, scale) {
      var s = [];
      for (var k = 0; k + 1 < flat.length; k += 2) s.push(f2(flat[k] / scale) + "," + f2(flat[k + 1] / scale));
      return s.join(" ");
    }

    var shownLeg = -1, shownPlan = -1;
    function drawLeg(leg) {
      var l = D.scene.legs[leg];
      clear(layers.map); clear(layers.goals); clear(layers.tree);
      l.obstacles.forEach(function (o) {
        if (o.poly) el("polygon", { points: o.poly.map(function (p) { return p.join(","); }).join(" "), "class": "obstacle" }, layers.map);
        else el("circle", { cx: o.c[0], cy: o.c[1], r: o.r, "class": "obstacle" }, layers.map);
      });
      el("rect", { x: 0, y: 0, width: l.w, height: l.h, "class": "walls" }, layers.map);
      l.goal.forEach(function (g, i) {
        el("circle", { cx: g[0], cy: g[1], r: l.tol, "class": "goal", stroke: col(i) }, layers.goals);
        el("path", { d: "M" + (g[0] - 0.3) + "," + g[1] + "h0.6M" + g[0] + "," + (g[1] - 0.3) + "v0.6", "class": "goalx", stroke: col(i) }, layers.goals);
      });
      if (leg === 0) D.scene.start.forEach(function (p, i) {
        el("rect", { x: p[0] - 0.5, y: p[1] - 0.5, width: 1, height: 1, "class": "start", stroke: col(i) }, layers.goals);
      });
      D.trees.filter(function (t) { return t.leg === leg; }).forEach(function (t) {
        var d = [];
        for (var k = 0; k + 3 < t.edges.length; k += 4)
          d.push("M" + f2(t.edges[k] / TS) + "," + f2(t.edges[k + 1] / TS) + "L" + f2(t.edges[k + 2] / TS) + "," + f2(t.edges[k + 3] / TS));
        el("path", { d: d.join(""), "class": "tree" }, layers.tree);
      });
      shownLeg = leg;
    }

    function drawPlans(leg, current) {
      clear(layers.plans);
      D.plans.forEach(function (p, j) {
        if (p.leg !== leg || j > current) return;
        p.paths.forEach(function (path, i) {
          el("polyline", { points: pts(path, S), "class": j === current ? "plan" : "plan old", stroke: col(i), "data-plan": j }, layers.plans);
        });
      });
      shownPlan = current;
    }

    // trails, agents and observed positions
    var trails = [], agents = [], obs = [];
    for (var i = 0; i < A; i++) {
      trails.push(el("polyline", { "class": "trail", id: "trail-" + i }, layers.trails));
      obs.push(el("circle", { r: 1.4 * D.scene.radius, "class": "obs", stroke: col(i), id: "obs-" + i, "data-agent": i }, layers.obs));
      agents.push(el("circle", { r: D.scene.radius, "class": "agent", fill: col(i), id: "agent-" + i, "data-agent": i }, layers.agents));
    }
    var bArrow = el("path", { "class": "field-b", id: "field-arrow" }, layers.field);
    var gArrow = el("path", { "class": "field-g", id: "grad-arrow" }, layers.field);
    var gMax = 1e-9;
    D.field.forEach(function (f) { gMax = Math.max(gMax, Math.hypot(f[2], f[3])); });

    function arrow(path, x, y, ang, len) {
      if (len <= 0) { path.setAttribute("d", ""); return; }
      var ex = x + len * Math.cos(ang), ey = y + len * Math.sin(ang), h = Math.min(0.6, len / 2);
      var a1 = ang + Math.PI - 0.45, a2 = ang + Math.PI + 0.45;
      path.setAttribute("d", "M" + f2(x) + "," + f2(y) + "L" + f2(ex) + "," + f2(ey) +
        "M" + f2(ex + h * Math.cos(a1)) + "," + f2(ey + h * Math.sin(a1)) + "L" + f2(ex) + "," + f2(ey) +
        "L" + f2(ex + h * Math.cos(a2)) + "," + f2(ey + h * Math.sin(a2)));
    }

    // events: markers appear at their time; the list seeks to them
    var marks = D.events.map(function (e, j) {
      var g = el("g", { "class": "event " + e.kind, "data-t": e.t, id: "event-" + j }, layers.events);
      var x = e.at[0], y = e.at[1], r = 0.6;
      if (e.kind === "contact" || e.kind === "wall")
        el("path", { d: "M" + (x - r) + "," + (y - r) + "L" + (x + r) + "," + (y + r) + "M" + (x - r) + "," + (y + r) + "L" + (x + r) + "," + (y - r) }, g);
      else el("path", { d: "M" + x + "," + (y - r) + "L" + (x + r) + "," + y + "L" + x + "," + (y + r) + "L" + (x - r) + "," + y + "Z" }, g);
      el("title", {}, g).textContent = e.t.toFixed(2) + " s: " + e.note;
      return g;
    });
    var list = $("events");
    D.events.forEach(function (e) {
      var li = document.createElement("li");
      var a = document.createElement("a");
      a.href = "#t=" + e.t;
      a.textContent = e.t.toFixed(2) + " s  " + e.note;
      a.className = e.kind;
      li.appendChild(a);
      list.appendChild(li);
    });
    if (!D.events.length) list.innerHTML = "<li>none</li>";

    // state
    var t = 0, frame = 0, playing = false, speed = 1, last = null;
    var scrub = $("scrub"), playBtn = $("play"), speedSel = $("speed"), treeBox = $("tree-toggle");
    scrub.max = T;

    function frameAt(time) {
      var lo = 0, hi = N - 1;
      if (N === 0 || time <= D.t[0]) return 0;
      while (lo < hi) {
        var mid = (lo + hi + 1) >> 1;
        if (D.t[mid] <= time + 1e-9) lo = mid; else hi = mid - 1;
      }
      return lo;
    }

    function render() {
      if (!N) return;
      var k = frame, leg = D.leg[k];
      if (leg !== shownLeg) { drawLeg(leg); shownPlan = -1; }
      if (D.plan[k] !== shownPlan) drawPlans(leg, D.plan[k]);
      var cx = 0, cy = 0;
      for (var i = 0; i < A; i++) {
        var x = D.truth[i][2 * k] / S, y = D.truth[i][2 * k + 1] / S;
        cx += x / A; cy += y / A;
        var a = agents[i];
        a.setAttribute("cx", x); a.setAttribute("cy", y);
        a.setAttribute("data-x", x.toFixed(2)); a.setAttribute("data-y", y.toFixed(2));
        a.setAttribute("data-t", D.t[k].toFixed(3));
        // the trail of the current leg up to this frame
        var from = k;
        while (from > 0 && D.leg[from - 1] === leg) from--;
        trails[i].setAttribute("points", pts(D.truth[i].slice(2 * from, 2 * k + 2), S));
        var o = obs[i], ox = D.obs.length ? D.obs[i][2 * k] : null, oy = D.obs.length ? D.obs[i][2 * k + 1] : null;
        if (ox === null || oy === null) {
          o.setAttribute("visibility", "hidden");
          o.setAttribute("data-x", ""); o.setAttribute("data-y", "");
        } else {
          o.setAttribute("visibility", "visible");
          o.setAttribute("cx", ox / S); o.setAttribute("cy", oy / S);
          o.setAttribute("data-x", (ox / S).toFixed(2)); o.setAttribute("data-y", (oy / S).toFixed(2));
        }
      }
      var f = D.field[k];
      arrow(bArrow, cx, cy, f[0] * Math.PI / 180, 2.5 * Math.cos(f[1] * Math.PI / 180));
      var g = Math.hypot(f[2], f[3]);
      arrow(gArrow, cx, cy, Math.atan2(f[3], f[2]), 3 * g / gMax);
      bArrow.setAttribute("data-theta", f[0]);
      D.events.forEach(function (e, j) {
        marks[j].setAttribute("visibility", e.t <= t + 1e-9 && D.leg[frameAt(e.t)] === leg ? "visible" : "hidden");
      });
      $("time").textContent = t.toFixed(2) + " / " + T.toFixed(2) + " s";
      $("frame-info").textContent = "leg " + (leg + 1) + " · plan " + (D.plan[k] + 1) + " (" + D.plans[D.plan[k]].reason + ")";
      $("field-info").textContent = "θ " + f[0].toFixed(1) + "°, α " + f[1].toFixed(1) + "°, G (" + f[2].toFixed(1) + ", " + f[3].toFixed(1) + ") mT/m";
      scrub.value = t;
      document.body.setAttribute("data-t", t.toFixed(3));
      document.body.setAttribute("data-frame", k);
      document.body.setAttribute("data-playing", playing);
      document.body.setAttribute("data-speed", speed);
      document.body.setAttribute("data-tree", treeBox.checked);
    }

    function seek(time) {
      t = Math.max(0, Math.min(T, time));
      frame = frameAt(t);
      render();
    }
    function setHash() {
      var h = "#t=" + t.toFixed(2) + (speed !== 1 ? "&speed=" + speed : "") + (treeBox.checked ? "&tree=1" : "");
      if (history.replaceState) history.replaceState(null, "", h);
    }
    // a timer, not animation frames: a headless browser's virtual clock runs timers exactly
    function tick() {
      if (!playing) return;
      var now = performance.now();
      if (last !== null) seek(t + (now - last) / 1000 * speed);
      last = now;
      if (t >= T) { setPlaying(false); setHash(); return; }
      setTimeout(tick, 16);
    }
    function setPlaying(p) {
      playing = p;
      playBtn.textContent = p ? "Pause" : "Play";
      document.body.setAttribute("data-playing", p);
      if (p) {
        if (t >= T) seek(0);
        last = null;
        setTimeout(tick, 16);
      }
    }
    function setTree(on) {
      treeBox.checked = on;
      layers.tree.setAttribute("visibility", on ? "visible" : "hidden");
      document.body.setAttribute("data-tree", on);
    }
    function fromHash() {
      var h = {};
      location.hash.replace(/^#/, "").split("&").forEach(function (kv) {
        var p = kv.split("=");
        if (p[0]) h[p[0]] = decodeURIComponent(p[1] || "");
      });
      if (h.speed && isFinite(+h.speed) && +h.speed > 0) { speed = +h.speed; speedSel.value = h.speed; }
      if (h.tree !== undefined) setTree(h.tree === "1");
      if (h.t !== undefined) seek(h.t === "end" ? T : +h.t || 0); else seek(t);
      if (h.play === "1") setPlaying(true);
    }

    playBtn.addEventListener("click", function () { setPlaying(!playing); if (!playing) setHash(); });
    scrub.addEventListener("input", function () { setPlaying(false); seek(+scrub.value); setHash(); });
    speedSel.addEventListener("change", function () { speed = +speedSel.value; render(); setHash(); });
    treeBox.addEventListener("change", function () { setTree(treeBox.checked); setHash(); });
    $("step-back").addEventListener("click", function () { setPlaying(false); seek(D.t[Math.max(0, frame - 1)]); setHash(); });
    $("step-fwd").addEventListener("click", function () { setPlaying(false); seek(D.t[Math.min(N - 1, frame + 1)]); setHash(); });
    document.addEventListener("keydown", function (e) {
      if (e.target.tagName === "INPUT" || e.target.tagName === "SELECT") return;
      if (e.key === " ") { e.preventDefault(); playBtn.click(); }
      else if (e.key === "ArrowRight") $("step-fwd").click();
      else if (e.key === "ArrowLeft") $("step-back").click();
    });
    window.addEventListener("hashchange", fromHash);
    setTree(D.trees.length > 0 && D.kind === "planned");
    fromHash();
  }
})();
