// The animation's player: reads the scene from the JSON beside it and draws it on the
// canvas. No network, no globals: everything hangs off the section element. Errors
// (thrown or logged) are written into the section's `.errors` block, which a headless
// browser's DOM dump shows; `data-ready` is set once the first frame is drawn.
(function () {
  "use strict";
  var root = document.getElementById("bgdsl-animation");
  var errors = root.querySelector(".errors");
  function report(message) {
    errors.hidden = false;
    errors.textContent += message + "\n";
  }
  window.addEventListener("error", function (e) {
    report("error: " + e.message + " (line " + e.lineno + ")");
  });
  var consoleError = console.error;
  console.error = function () {
    report("console.error: " + Array.prototype.join.call(arguments, " "));
    consoleError.apply(console, arguments);
  };
  try {
    start();
  } catch (e) {
    report("error: " + (e && e.stack ? e.stack : String(e)));
  }

  function start() {
    var scene = JSON.parse(root.querySelector(".data").textContent);
    var canvas = root.querySelector("canvas");
    var ctx = canvas.getContext("2d");
    var play = root.querySelector(".play");
    var scrub = root.querySelector(".scrub");
    var speed = root.querySelector(".speed");
    var timeOut = root.querySelector(".time");
    var angleOut = root.querySelector(".angle");
    var legend = root.querySelector(".legend");
    var times = scene.times;
    var n = times.length;
    var colours = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e",
      "#8c564b", "#e377c2", "#17becf", "#7f7f7f", "#bcbd22"];
    var plane = scene.view !== "orbit" ? scene.view.plane : null;
    // The address may set the 3-D view's turn: `#t=0.3&yaw=0.5&pitch=0.2` (radians).
    function fromHash(key, fallback) {
      var m = new RegExp("(?:^#|&)" + key + "=([0-9.eE+-]+)").exec(window.location.hash);
      return m && isFinite(Number(m[1])) ? Number(m[1]) : fallback;
    }
    var yaw = fromHash("yaw", -0.6), pitch = fromHash("pitch", 0.35);

    scene.bodies.forEach(function (body, i) {
      var item = document.createElement("li");
      var swatch = document.createElement("span");
      swatch.className = "swatch";
      swatch.style.background = colours[i % colours.length];
      item.appendChild(swatch);
      item.appendChild(document.createTextNode(body.name));
      legend.appendChild(item);
    });

    // A body's shape points in frame 0 at frame k.
    function corners(body) {
      var s = body.shape;
      if (s.box) {
        var out = [];
        for (var c = 0; c < 8; c++) {
          out.push([(c & 1 ? 0.5 : -0.5) * s.box[0], (c & 2 ? 0.5 : -0.5) * s.box[1],
            (c & 4 ? 0.5 : -0.5) * s.box[2]]);
        }
        return out;
      }
      if (s.segment) return [s.segment[0], s.segment[1]];
      return [[0, 0, 0]];
    }
    var local = scene.bodies.map(corners);
    function world(i, k) {
      var b = scene.bodies[i], p = b.p, r = b.r;
      return local[i].map(function (q) {
        var out = [];
        for (var a = 0; a < 3; a++) {
          out.push(p[3 * k + a] + r[9 * k + a] * q[0] + r[9 * k + 3 + a] * q[1] +
            r[9 * k + 6 + a] * q[2]);
        }
        return out;
      });
    }
    function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
    // Frame 0 to the view's (right, up) before scaling.
    function project(q) {
      if (plane) return [dot(q, plane.u), dot(q, plane.v)];
      var cy = Math.cos(yaw), sy = Math.sin(yaw), cp = Math.cos(pitch), sp = Math.sin(pitch);
      var x = cy * q[0] + sy * q[2], z = -sy * q[0] + cy * q[2];
      return [x, cp * q[1] - sp * z];
    }

    // Bounds over the whole run, so the picture never jumps: a box in the plane view, a
    // sphere (whatever the turn) in the orbit view.
    var all = [];
    for (var i = 0; i < scene.bodies.length; i++) {
      for (var k = 0; k < n; k++) {
        world(i, k).forEach(function (q) { if (finite(q)) all.push(q); });
      }
    }
    scene.ground.forEach(function (q) { all.push(q); });
    function finite(q) { return isFinite(q[0]) && isFinite(q[1]) && isFinite(q[2]); }
    var lo = [Infinity, Infinity], hi = [-Infinity, -Infinity], centre = [0, 0, 0], radius = 0;
    if (plane) {
      all.forEach(function (q) {
        var s = project(q);
        for (var a = 0; a < 2; a++) { lo[a] = Math.min(lo[a], s[a]); hi[a] = Math.max(hi[a], s[a]); }
      });
    } else {
      all.forEach(function (q) { for (var a = 0; a < 3; a++) centre[a] += q[a] / all.length; });
      all.forEach(function (q) {
        radius = Math.max(radius, Math.hypot(q[0] - centre[0], q[1] - centre[1], q[2] - centre[2]));
      });
    }
    if (!(hi[0] > lo[0])) { lo[0] -= 0.5; hi[0] += 0.5; }
    if (!(hi[1] > lo[1])) { lo[1] -= 0.5; hi[1] += 0.5; }
    if (!(radius > 0)) radius = 1;
    var aspect = plane ? Math.min(1.5, Math.max(0.35, (hi[1] - lo[1]) / (hi[0] - lo[0]))) : 0.75;

    var width = 0, height = 0, scale = 1, offset = [0, 0];
    function layout() {
      width = Math.min(960, Math.max(200, root.clientWidth || 800));
      height = Math.min(560, Math.round(width * aspect));
      var ratio = window.devicePixelRatio || 1;
      canvas.width = Math.round(width * ratio);
      canvas.height = Math.round(height * ratio);
      canvas.style.width = width + "px";
      canvas.style.height = height + "px";
      ctx.setTransform(ratio, 0, 0, ratio, 0, 0);
      var margin = 24;
      if (plane) {
        scale = Math.min((width - 2 * margin) / (hi[0] - lo[0]), (height - 2 * margin) / (hi[1] - lo[1]));
        offset = [width / 2 - scale * (lo[0] + hi[0]) / 2, height / 2 + scale * (lo[1] + hi[1]) / 2];
      } else {
        scale = (Math.min(width, height) / 2 - margin) / radius;
        var c = project(centre);
        offset = [width / 2 - scale * c[0], height / 2 + scale * c[1]];
      }
    }
    // Frame 0 to canvas pixels (CSS), y downwards.
    function pixel(q) {
      var s = project(q);
      return [offset[0] + scale * s[0], offset[1] - scale * s[1]];
    }
    function hull(points) {
      var p = points.slice().sort(function (a, b) { return a[0] - b[0] || a[1] - b[1]; });
      if (p.length < 3) return p;
      function cross(o, a, b) { return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]); }
      var lower = [], upper = [];
      p.forEach(function (q) {
        while (lower.length >= 2 && cross(lower[lower.length - 2], lower[lower.length - 1], q) <= 0) lower.pop();
        lower.push(q);
      });
      p.slice().reverse().forEach(function (q) {
        while (upper.length >= 2 && cross(upper[upper.length - 2], upper[upper.length - 1], q) <= 0) upper.pop();
        upper.push(q);
      });
      return lower.slice(0, -1).concat(upper.slice(0, -1));
    }

    var frame = 0;
    function draw(k) {
      frame = k;
      ctx.fillStyle = "#fff";
      ctx.fillRect(0, 0, width, height);
      var centres = {};
      scene.bodies.forEach(function (body, i) {
        var pts = world(i, k);
        if (!pts.every(finite)) return;
        var colour = colours[i % colours.length];
        var px = pts.map(pixel);
        ctx.strokeStyle = colour;
        ctx.fillStyle = colour;
        if (body.shape.box) {
          var h = hull(px);
          ctx.beginPath();
          h.forEach(function (q, j) { if (j) ctx.lineTo(q[0], q[1]); else ctx.moveTo(q[0], q[1]); });
          ctx.closePath();
          ctx.globalAlpha = 0.35;
          ctx.fill();
          ctx.globalAlpha = 1;
          ctx.lineWidth = 2;
          ctx.stroke();
        } else if (body.shape.segment) {
          ctx.lineWidth = 5;
          ctx.lineCap = "round";
          ctx.beginPath();
          ctx.moveTo(px[0][0], px[0][1]);
          ctx.lineTo(px[1][0], px[1][1]);
          ctx.stroke();
        } else {
          ctx.beginPath();
          ctx.arc(px[0][0], px[0][1], 5, 0, 2 * Math.PI);
          ctx.fill();
        }
        centres[body.name] = pixel([body.p[3 * k], body.p[3 * k + 1], body.p[3 * k + 2]]);
      });
      scene.ground.forEach(function (q) {
        var g = pixel(q);
        ctx.lineWidth = 1.5;
        ctx.strokeStyle = "#222";
        ctx.fillStyle = "#fff";
        ctx.beginPath();
        ctx.moveTo(g[0], g[1]);
        ctx.lineTo(g[0] - 8, g[1] + 12);
        ctx.lineTo(g[0] + 8, g[1] + 12);
        ctx.closePath();
        ctx.fill();
        ctx.stroke();
        for (var h = -8; h < 8; h += 4) {
          ctx.beginPath();
          ctx.moveTo(g[0] + h + 4, g[1] + 12);
          ctx.lineTo(g[0] + h, g[1] + 16);
          ctx.stroke();
        }
        ctx.beginPath();
        ctx.arc(g[0], g[1], 3, 0, 2 * Math.PI);
        ctx.fill();
        ctx.stroke();
      });
      axes();
      scrub.value = k;
      timeOut.textContent = "t = " + times[k].toFixed(3) + " s";
      if (scene.angle) {
        var deg = scene.angle.deg[k];
        // The model's angle is unwrapped (it counts turns); shown within one turn, with the turn.
        var text = "–";
        if (deg !== null) {
          var turn = Math.floor(deg / 360);
          text = (deg - 360 * turn).toFixed(1) + "° (turn " + turn + ")";
        }
        angleOut.textContent = scene.angle.label + " = " + text;
      }
      var rect = canvas.getBoundingClientRect();
      root.dataset.frame = String(k);
      root.dataset.canvas = JSON.stringify([rect.left + window.scrollX, rect.top + window.scrollY]);
      root.dataset.centres = JSON.stringify(centres);
      root.dataset.ground = JSON.stringify(scene.ground.map(pixel));
    }

    // Frame 0's axes in the lower left corner, as the view shows them (an axis seen
    // end-on is left out).
    function axes() {
      var o = [36, height - 36];
      var names = ["X0", "Y0", "Z0"];
      ctx.font = "12px sans-serif";
      ctx.lineWidth = 1.5;
      ctx.strokeStyle = "#555";
      ctx.fillStyle = "#555";
      for (var a = 0; a < 3; a++) {
        var e = [0, 0, 0];
        e[a] = 1;
        var s = project(e);
        if (Math.hypot(s[0], s[1]) < 0.2) continue;
        var tip = [o[0] + 24 * s[0], o[1] - 24 * s[1]];
        ctx.beginPath();
        ctx.moveTo(o[0], o[1]);
        ctx.lineTo(tip[0], tip[1]);
        ctx.stroke();
        ctx.fillText(names[a], o[0] + 30 * s[0] - 7, o[1] - 30 * s[1] + 4);
      }
    }

    // The frame shown at time t: the last one at or before it.
    function frameAt(t) {
      var a = 0, b = n - 1;
      if (t <= times[0]) return 0;
      while (a < b) {
        var m = (a + b + 1) >> 1;
        if (times[m] <= t) a = m; else b = m - 1;
      }
      return a;
    }

    var playing = false, simTime = times[0], last = null;
    function setPlaying(on) {
      playing = on;
      play.textContent = on ? "Pause" : "Play";
      last = null;
      if (on) requestAnimationFrame(tick);
    }
    function tick(now) {
      if (!playing) return;
      if (last !== null) {
        simTime += (now - last) / 1000 * Number(speed.value);
        if (simTime > times[n - 1]) simTime = times[0];
      }
      last = now;
      draw(frameAt(simTime));
      requestAnimationFrame(tick);
    }
    play.addEventListener("click", function () { setPlaying(!playing); });
    scrub.max = String(n - 1);
    scrub.addEventListener("input", function () {
      var k = Number(scrub.value);
      simTime = times[k];
      draw(k);
    });
    var dragging = null;
    if (!plane) {
      canvas.style.cursor = "grab";
      canvas.addEventListener("mousedown", function (e) { dragging = [e.clientX, e.clientY]; });
      window.addEventListener("mouseup", function () { dragging = null; });
      window.addEventListener("mousemove", function (e) {
        if (!dragging) return;
        yaw += (e.clientX - dragging[0]) * 0.01;
        pitch = Math.max(-1.5, Math.min(1.5, pitch + (e.clientY - dragging[1]) * 0.01));
        dragging = [e.clientX, e.clientY];
        layout();
        draw(frame);
      });
    }
    window.addEventListener("resize", function () { layout(); draw(frame); });

    layout();
    // `#t=0.3` in the address: a still at that time, paused.
    var still = fromHash("t", null);
    if (still !== null) {
      simTime = still;
      draw(frameAt(simTime));
      setPlaying(false);
    } else {
      draw(0);
      setPlaying(n > 1);
    }
    root.dataset.ready = "1";
  }
})();
