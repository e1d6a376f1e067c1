// freefloat report page: one animation per plan (canvas), play/pause and a time slider; the arm
// is drawn from its points (base, joints, tip), for any number of links.
// No network, no external scripts. When every canvas has drawn its first frame, the body gets
// data-status="ok" and data-painted = the smallest count of non-background pixels of a canvas;
// a script error sets data-status="error: ..." instead (checked by the browser test).
"use strict";
(function () {
  var body = document.body;
  var failed = false;
  function fail(message) {
    failed = true;
    body.setAttribute("data-status", "error: " + message);
    var box = document.getElementById("script-error");
    if (box) {
      box.textContent = "Script error: " + message;
      box.hidden = false;
    }
  }
  window.onerror = function (message, source, line) {
    fail(message + " (line " + line + ")");
    return false;
  };

  var BACKGROUND = [255, 255, 255];
  // Link colours, from the base outwards (Okabe and Ito; links 1 and 2 as in the 2-link figures).
  var LINK_COLOURS = ["#0072b2", "#009e73", "#cc79a7", "#e69f00", "#56b4e9", "#f0e442"];
  function linkColour(k) { return LINK_COLOURS[k % LINK_COLOURS.length]; }
  // A joint at its position range or velocity limit (>= 99 %) and the link it drives
  // (plot/animation.rs, AT_LIMIT_COLOUR); anim.at_limit lists them per frame, counted from 1.
  var AT_LIMIT_COLOUR = "#e8000b";
  function atLimit(anim, i, joint) {
    return Boolean(anim.at_limit && anim.at_limit[i] && anim.at_limit[i].indexOf(joint) >= 0);
  }
  // A frame is [base x, y, joint 1 x, y, .., joint n x, y, tip x, y]: n links.
  function linkCount(anim) { return anim.points[0].length / 2 - 2; }
  // The shapes (issue 21, plot/scene.rs): anim.scene.bodies[0] is the base's outlines in its
  // frame (at its centre of mass, angle phi), bodies[k] link k's (at joint k, along the link);
  // obstacles are in the inertial frame.
  var OBSTACLE_COLOUR = "#5f5f5f";
  function bodyPoses(p, phi) {
    var poses = [[p[0], p[1], phi]];
    for (var k = 1; 2 * k + 3 < p.length; k++) {
      poses.push([p[2 * k], p[2 * k + 1], Math.atan2(p[2 * k + 3] - p[2 * k + 1], p[2 * k + 2] - p[2 * k])]);
    }
    return poses;
  }
  function placed(outline, pose) {
    var c = Math.cos(pose[2]), s = Math.sin(pose[2]);
    return outline.map(function (q) { return [pose[0] + c * q[0] - s * q[1], pose[1] + s * q[0] + c * q[1]]; });
  }
  // Every body's outlines placed at frame i: [[body, outline], ..].
  function placedBodies(anim, i) {
    var out = [];
    if (!anim.scene) return out;
    var poses = bodyPoses(anim.points[i], anim.phi[i]);
    anim.scene.bodies.forEach(function (outlines, body) {
      outlines.forEach(function (o) { if (poses[body]) out.push([body, placed(o, poses[body])]); });
    });
    return out;
  }

  function bounds(anim) {
    var half = Math.hypot(anim.base_size[0], anim.base_size[1]) / 2;
    var b = { x0: -half, x1: half, y0: -half, y1: half };
    anim.points.forEach(function (p) {
      for (var k = 0; k < p.length; k += 2) {
        var r = k === 0 ? half : 0.05;
        b.x0 = Math.min(b.x0, p[k] - r);
        b.x1 = Math.max(b.x1, p[k] + r);
        b.y0 = Math.min(b.y0, p[k + 1] - r);
        b.y1 = Math.max(b.y1, p[k + 1] + r);
      }
    });
    function take(q) {
      b.x0 = Math.min(b.x0, q[0]); b.x1 = Math.max(b.x1, q[0]);
      b.y0 = Math.min(b.y0, q[1]); b.y1 = Math.max(b.y1, q[1]);
    }
    if (anim.scene) {
      anim.scene.obstacles.forEach(function (o) { o.forEach(take); });
      anim.points.forEach(function (p, i) {
        placedBodies(anim, i).forEach(function (bo) { bo[1].forEach(take); });
      });
    }
    return b;
  }

  function Animation(root, anim) {
    var canvas = document.createElement("canvas");
    canvas.width = 640;
    canvas.height = 560;
    canvas.setAttribute("aria-label", "animation of " + anim.title);
    var controls = document.createElement("div");
    controls.className = "controls";
    var button = document.createElement("button");
    button.type = "button";
    button.textContent = "Play";
    var slider = document.createElement("input");
    slider.type = "range";
    slider.min = "0";
    slider.max = String(anim.t.length - 1);
    slider.value = "0";
    slider.step = "1";
    slider.setAttribute("aria-label", "time");
    var label = document.createElement("span");
    label.className = "time";
    controls.appendChild(button);
    controls.appendChild(slider);
    controls.appendChild(label);
    root.appendChild(canvas);
    root.appendChild(controls);

    var ctx = canvas.getContext("2d");
    var b = bounds(anim);
    var margin = 20;
    var links = linkCount(anim);
    var entries = [
      ["+", "#999", "centre of mass of the system (fixed)"],
      ["bar", "#444", "base to mounting point (a, b)"]
    ];
    for (var k = 0; k < links; k++) entries.push(["bar", linkColour(k), "link " + (k + 1)]);
    entries.push(["line", "#d55e00", "end-effector path"]);
    entries.push(["line", "#0072b2", "base's centre of mass path"]);
    if (anim.at_limit) entries.push(["bar", AT_LIMIT_COLOUR, "joint at its limit (\u2265 99 %)"]);
    var scene = anim.scene;
    var least = scene && scene.least;
    if (scene && scene.obstacles.length) entries.push(["bar", OBSTACLE_COLOUR, "obstacle"]);
    if (least) entries.push(["line", least.colour, "least clearance (nearest points)"]);
    if (least) {
      // A button that shows the moment of least clearance.
      var goLeast = document.createElement("button");
      goLeast.type = "button";
      goLeast.textContent = "Least clearance";
      controls.appendChild(goLeast);
    }
    // The legend in rows under the drawing: entries left to right, a new row when the next
    // would pass the right edge, each label measured with the canvas's font, so that no entry
    // overlaps another (two fixed columns did; the GIF frames' legend is laid out the same way,
    // plot/legend.rs).
    ctx.font = "13px sans-serif";
    var placed = [];
    var rows = 1;
    (function () {
      var x = 10, row = 0;
      entries.forEach(function (e) {
        var width = 32 + Math.ceil(ctx.measureText(e[2]).width);
        if (x > 10 && x + width > canvas.width - 10) { x = 10; row += 1; }
        placed.push([e, x, row]);
        x += width + 20;
      });
      rows = row + 1;
    })();
    // The strip under the drawing for the legend [px].
    var LEGEND = 12 + 20 * rows;
    var scale = Math.min(
      (canvas.width - 2 * margin) / (b.x1 - b.x0),
      (canvas.height - 2 * margin - 24 - LEGEND) / (b.y1 - b.y0)
    );
    var cx = (b.x0 + b.x1) / 2;
    var cy = (b.y0 + b.y1) / 2;
    function sx(x) { return canvas.width / 2 + (x - cx) * scale; }
    function sy(y) { return (canvas.height - LEGEND) / 2 + 12 - (y - cy) * scale; }

    // A scale bar of a round length (0.1, 0.2, 0.5, 1, 2 ... m) about 120 px long.
    var BAR_STEPS = [0.1, 0.2, 0.5, 1, 2, 5, 10];
    var barLength = BAR_STEPS.reduce(function (best, m) {
      return Math.abs(m * scale - 120) < Math.abs(best * scale - 120) ? m : best;
    }, BAR_STEPS[0]);
    function legend() {
      var top = canvas.height - LEGEND + 8;
      ctx.strokeStyle = "#ddd";
      ctx.lineWidth = 1;
      ctx.beginPath();
      ctx.moveTo(0, top - 6);
      ctx.lineTo(canvas.width, top - 6);
      ctx.stroke();
      ctx.font = "13px sans-serif";
      placed.forEach(function (p) {
        var e = p[0], x = p[1], y = top + 20 * p[2] + 6;
        ctx.strokeStyle = e[1];
        ctx.fillStyle = e[1];
        ctx.lineWidth = e[0] === "bar" ? 4 : 2;
        ctx.beginPath();
        if (e[0] === "+") {
          ctx.moveTo(x + 6, y); ctx.lineTo(x + 18, y); ctx.moveTo(x + 12, y - 6); ctx.lineTo(x + 12, y + 6);
        } else {
          ctx.moveTo(x, y); ctx.lineTo(x + 24, y);
        }
        ctx.stroke();
        ctx.fillStyle = "#000";
        ctx.fillText(e[2], x + 32, y + 4);
      });
      // The scale bar, top right (as in the GIF frames): the legend's rows take the full width.
      var x1 = canvas.width - 20, x0 = x1 - barLength * scale, y = 30;
      ctx.strokeStyle = "#000";
      ctx.lineWidth = 2;
      ctx.beginPath();
      ctx.moveTo(x0, y - 5); ctx.lineTo(x0, y); ctx.lineTo(x1, y); ctx.lineTo(x1, y - 5);
      ctx.stroke();
      ctx.fillStyle = "#000";
      ctx.textAlign = "center";
      ctx.fillText(barLength + " m", (x0 + x1) / 2, y - 8);
      ctx.textAlign = "start";
    }

    function line(points, colour, width) {
      ctx.strokeStyle = colour;
      ctx.lineWidth = width;
      ctx.beginPath();
      points.forEach(function (p, i) {
        if (i === 0) ctx.moveTo(sx(p[0]), sy(p[1]));
        else ctx.lineTo(sx(p[0]), sy(p[1]));
      });
      ctx.stroke();
    }
    function shape(points, fill, stroke, width) {
      ctx.beginPath();
      points.forEach(function (q, k) {
        if (k === 0) ctx.moveTo(sx(q[0]), sy(q[1]));
        else ctx.lineTo(sx(q[0]), sy(q[1]));
      });
      ctx.closePath();
      if (fill) { ctx.fillStyle = fill; ctx.fill(); }
      if (!(width > 0)) return;
      ctx.strokeStyle = stroke;
      ctx.lineWidth = width;
      ctx.lineJoin = "round";
      ctx.stroke();
    }
    function dot(p, r, colour) {
      ctx.fillStyle = colour;
      ctx.beginPath();
      ctx.arc(sx(p[0]), sy(p[1]), r, 0, 2 * Math.PI);
      ctx.fill();
    }

    var frame = 0;
    function draw(i) {
      frame = i;
      var p = anim.points[i];
      var phi = anim.phi[i];
      ctx.fillStyle = "rgb(" + BACKGROUND.join(",") + ")";
      ctx.fillRect(0, 0, canvas.width, canvas.height);
      // The system's centre of mass, fixed at the origin (zero linear momentum).
      line([[-0.05, 0], [0.05, 0]], "#999", 1);
      line([[0, -0.05], [0, 0.05]], "#999", 1);
      // The end-effector path: whole (faint) and travelled so far.
      var path = anim.points.map(function (q) { return [q[q.length - 2], q[q.length - 1]]; });
      line(path, "#d9d9d9", 1.5);
      line(path.slice(0, i + 1), "#d55e00", 2);
      // The base's centre of mass: where the base drifts (same kinematics, model::kinematics).
      var drift = anim.points.map(function (q) { return [q[0], q[1]]; });
      line(drift, "#dbe6f0", 1.5);
      line(drift.slice(0, i + 1), "#0072b2", 2);
      // The obstacles, then each body's shapes (the base's in grey, a link's in its colour).
      if (scene) {
        scene.obstacles.forEach(function (o) { shape(o, "rgba(95, 95, 95, 0.45)", OBSTACLE_COLOUR, 1.5); });
        placedBodies(anim, i).forEach(function (bo) {
          if (bo[0] === 0) shape(bo[1], "rgba(120, 120, 120, 0.35)", "#444", 1.5);
          else {
            ctx.globalAlpha = 0.25;
            shape(bo[1], linkColour(bo[0] - 1), linkColour(bo[0] - 1), 0);
            ctx.globalAlpha = 1;
            shape(bo[1], null, linkColour(bo[0] - 1), 1.5);
          }
        });
      }
      // The base: a rectangle at its orientation, centred at its centre of mass (unless its
      // shapes are drawn).
      var c = Math.cos(phi), s = Math.sin(phi);
      var w = anim.base_size[0] / 2, h = anim.base_size[1] / 2;
      var corners = [[-w, -h], [w, -h], [w, h], [-w, h], [-w, -h]].map(function (k) {
        return [p[0] + c * k[0] - s * k[1], p[1] + s * k[0] + c * k[1]];
      });
      if (!(scene && scene.bodies[0] && scene.bodies[0].length)) {
        ctx.fillStyle = "rgba(120, 120, 120, 0.35)";
        ctx.beginPath();
        corners.forEach(function (q, k) {
          if (k === 0) ctx.moveTo(sx(q[0]), sy(q[1]));
          else ctx.lineTo(sx(q[0]), sy(q[1]));
        });
        ctx.fill();
        line(corners, "#444", 2);
      }
      // The base's own x axis, to show its orientation.
      line([[p[0], p[1]], [p[0] + c * w, p[1] + s * w]], "#444", 1);
      // From the base's centre of mass to the mounting point (a, b).
      line([[p[0], p[1]], [p[2], p[3]]], "#444", 3);
      // The links, each from its joint to the next (the last to the tip), then the joints.
      for (var k = 0; k < links; k++) {
        var colour = atLimit(anim, i, k + 1) ? AT_LIMIT_COLOUR : linkColour(k);
        line([[p[2 * k + 2], p[2 * k + 3]], [p[2 * k + 4], p[2 * k + 5]]], colour, 6);
      }
      dot([p[0], p[1]], 4, "#444");
      for (var j = 1; j <= links; j++) {
        if (atLimit(anim, i, j)) dot([p[2 * j], p[2 * j + 1]], 8, AT_LIMIT_COLOUR);
        else dot([p[2 * j], p[2 * j + 1]], 5, "#000");
      }
      dot([p[p.length - 2], p[p.length - 1]], 5, "#d55e00");
      // The least clearance: at its sample, the pair's outlines and their nearest points; its
      // caption above the legend at every sample.
      if (least) {
        if (i === least.sample) {
          least.outlines.forEach(function (o) { shape(o, null, least.colour, 3); });
          if (least.points) {
            line(least.points, least.colour, 2);
            least.points.forEach(function (q) { dot(q, 3.5, least.colour); });
          }
        }
        ctx.fillStyle = least.colour;
        ctx.font = "13px sans-serif";
        ctx.fillText(least.caption, 10, canvas.height - LEGEND - 4);
      }
      ctx.fillStyle = "#000";
      ctx.font = "15px sans-serif";
      var text = "t = " + anim.t[i].toFixed(2) + " s   \u03c6 = " + (phi * 180 / Math.PI).toFixed(1) + " deg";
      ctx.fillText(text, 10, 20);
      legend();
      label.textContent = text;
      slider.value = String(i);
    }

    var playing = false;
    var start = 0;
    var startTime = 0;
    function tick(now) {
      if (!playing) return;
      var t = anim.t[0] + (now - start) / 1000 + startTime;
      var last = anim.t.length - 1;
      if (t > anim.t[last]) {
        playing = false;
        button.textContent = "Play";
        draw(last);
        return;
      }
      var i = frame;
      while (i < last && anim.t[i + 1] <= t) i++;
      if (i !== frame) draw(i);
      window.requestAnimationFrame(tick);
    }
    button.addEventListener("click", function () {
      playing = !playing;
      button.textContent = playing ? "Pause" : "Play";
      if (playing) {
        if (frame >= anim.t.length - 1) draw(0);
        start = performance.now();
        startTime = anim.t[frame] - anim.t[0];
        window.requestAnimationFrame(tick);
      }
    });
    slider.addEventListener("input", function () {
      playing = false;
      button.textContent = "Play";
      draw(Number(slider.value));
    });
    if (least) {
      goLeast.addEventListener("click", function () {
        playing = false;
        button.textContent = "Play";
        draw(least.sample);
      });
    }
    draw(0);

    this.seek = function (t) {
      var i = 0;
      while (i < anim.t.length - 1 && anim.t[i + 1] <= t) i++;
      draw(i);
    };
    this.painted = function () {
      var data = ctx.getImageData(0, 0, canvas.width, canvas.height).data;
      var n = 0;
      for (var k = 0; k < data.length; k += 4) {
        if (data[k] !== BACKGROUND[0] || data[k + 1] !== BACKGROUND[1] || data[k + 2] !== BACKGROUND[2]) n++;
      }
      return n;
    };
  }

  try {
    var data = JSON.parse(document.getElementById("animations").textContent);
    var byId = {};
    data.forEach(function (a) { byId[a.id] = a; });
    var made = [];
    Array.prototype.forEach.call(document.querySelectorAll(".anim"), function (root) {
      var anim = byId[root.getAttribute("data-case")];
      if (!anim) throw new Error("no animation data for " + root.getAttribute("data-case"));
      made.push(new Animation(root, anim));
    });
    // `#only=fig15&t=5`: show only that figure, its animation at t = 5 s (for screenshots).
    var hash = {};
    window.location.hash.replace(/^#/, "").split("&").forEach(function (kv) {
      var p = kv.split("=");
      if (p.length === 2) hash[p[0]] = decodeURIComponent(p[1]);
    });
    if (hash.only) {
      Array.prototype.forEach.call(document.body.children, function (el) {
        if (el.tagName !== "SCRIPT" && el.id !== hash.only && el.id !== "script-error") el.hidden = true;
      });
    }
    if (hash.t) made.forEach(function (a) { a.seek(Number(hash.t)); });
    var counts = made.map(function (a) { return a.painted(); });
    body.setAttribute("data-canvases", String(made.length));
    // The page's width, to check that a narrow screen does not scroll sideways.
    body.setAttribute("data-width", String(document.documentElement.scrollWidth));
    body.setAttribute("data-viewport", String(document.documentElement.clientWidth));
    body.setAttribute("data-painted", String(counts.length ? Math.min.apply(null, counts) : 0));
    if (!failed) body.setAttribute("data-status", "ok");
  } catch (e) {
    fail(String(e && e.message ? e.message : e));
  }
})();
