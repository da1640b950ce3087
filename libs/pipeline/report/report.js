// The report page of `hmt-slam run --report`: steps through the run held in
// data.js (window.HMT_REPORT, written by libs/pipeline/src/report.cc).
// Plain JS on canvases, no library, so the page opens from file:// anywhere.
// Any error is written into #errors (and <body data-report="error">); a page
// that drew everything says <body data-report="ready">: the browser test
// reads both.
"use strict";
(function () {
  const errors = document.getElementById("errors");
  function fail(message) {
    errors.textContent += message + "\n";
    document.body.dataset.report = "error";
  }
  window.addEventListener("error", (e) => {
    const where = e.filename ? " (" + e.filename.split("/").pop() + ":" + e.lineno + ")" : "";
    fail("script error: " + e.message + where);
  });

  const D = window.HMT_REPORT;
  if (!D || D.format !== 1) {
    fail("data.js did not load or is not a report of format 1: rerun hmt-slam run --report");
    return;
  }
  const steps = D.steps || [];
  const traj = D.trajectory || [];
  const n = Math.min(steps.length, traj.length);
  if (n === 0) {
    fail("data.js holds no steps");
    return;
  }
  const first = D.first_step || 0;

  // Colours by area id: tab10 and its light half, consecutive ids apart.
  const PALETTE = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b",
    "#e377c2", "#bcbd22", "#17becf", "#aec7e8", "#ffbb78", "#98df8a", "#ff9896",
    "#c5b0d5", "#c49c94", "#f7b6d2", "#dbdb8d", "#9edae5"];
  const areaColour = (a) => PALETTE[((a - 1) % PALETTE.length + PALETTE.length) % PALETTE.length];
  const fmt = (v, d) => (v === null || v === undefined ? "-" : Number(v).toFixed(d));
  // data.js rounds probabilities to 1e-6: a 0 there is below that.
  const fmtP = (p) => (p === 0 ? "< 1e-6" : p >= 0.001 ? p.toFixed(3) : p.toExponential(1));
  const isP = (p) => (p === 0 ? "< 1e-6" : "= " + fmtP(p));  // "P " + isP(p)

  // ---- the run's totals -------------------------------------------------
  const S = D.summary || {};
  const input = String(S.input || "");
  document.getElementById("title").textContent = "HMT-SLAM run: " + input.split("/").pop();
  document.title = "HMT-SLAM report: " + input.split("/").pop();
  document.getElementById("totals").textContent =
    input + " | " + (S.scans || n) + " scans, " + (S.particles || "?") + " particles | " +
    (S.areas || 0) + " areas, " + (S.arcs || 0) + " arcs | loop closures accepted: " +
    (S.loop_closures_accepted || 0) + " | new-area events: " + (S.new_area_events || 0) +
    " | hypotheses at most: " + (S.max_hypotheses_alive || "?");

  // ---- state and controls -----------------------------------------------
  // The last step, or the one the address asks for: index.html#step=120.
  const asked = /(?:^#|&)step=(\d+)/.exec(window.location.hash);
  let cur = asked ? Math.max(0, Math.min(n - 1, Number(asked[1]) - first)) : n - 1;
  const slider = document.getElementById("slider");
  slider.max = String(n - 1);
  slider.value = String(cur);
  const readout = document.getElementById("readout");

  function setStep(i) {
    cur = Math.max(0, Math.min(n - 1, Math.round(i)));
    slider.value = String(cur);
    render();
  }
  slider.addEventListener("input", () => setStep(Number(slider.value)));
  document.getElementById("prev").addEventListener("click", () => setStep(cur - 1));
  document.getElementById("next").addEventListener("click", () => setStep(cur + 1));
  let timer = null;
  const playButton = document.getElementById("play");
  function togglePlay() {
    if (timer) {
      clearInterval(timer);
      timer = null;
      playButton.innerHTML = "&#9654;";
      return;
    }
    if (cur >= n - 1) setStep(0);
    const stride = Math.max(1, Math.round(n / 600));
    timer = setInterval(() => {
      if (cur >= n - 1) togglePlay();
      else setStep(cur + stride);
    }, 40);
    playButton.innerHTML = "&#10074;&#10074;";
  }
  playButton.addEventListener("click", togglePlay);
  document.addEventListener("keydown", (e) => {
    if (e.target === slider && !e.shiftKey) return;  // the slider steps by itself
    const moves = { ArrowLeft: -1, ArrowRight: 1, PageUp: -100, PageDown: 100 };
    if (e.key in moves) setStep(cur + moves[e.key] * (e.shiftKey && Math.abs(moves[e.key]) === 1 ? 10 : 1));
    else if (e.key === "Home") setStep(0);
    else if (e.key === "End") setStep(n - 1);
    else if (e.key === " ") togglePlay();
    else return;
    e.preventDefault();
  });

  // ---- the map ------------------------------------------------------------
  const M = D.map;
  const mapCanvas = document.getElementById("map");
  const mapCtx = mapCanvas.getContext("2d");
  const mapImage = new Image();
  let mapReady = false;
  // Where map.png is drawn on the canvas: scale and offset (fit, centred).
  // Fitted whole at first; the wheel zooms about the pointer, a drag pans,
  // a double click fits it again.
  const fit = {};
  function fitMap() {
    fit.s = Math.min(mapCanvas.width / M.width, mapCanvas.height / M.height);
    fit.x = (mapCanvas.width - M.width * fit.s) / 2;
    fit.y = (mapCanvas.height - M.height * fit.s) / 2;
  }
  fitMap();
  const canvasPoint = (e) => {
    const r = mapCanvas.getBoundingClientRect();
    return [((e.clientX - r.left) * mapCanvas.width) / r.width, ((e.clientY - r.top) * mapCanvas.height) / r.height];
  };
  mapCanvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    const [px, py] = canvasPoint(e);
    const z = Math.exp(-e.deltaY * 0.002);
    fit.x = px - (px - fit.x) * z;
    fit.y = py - (py - fit.y) * z;
    fit.s *= z;
    drawMap();
  }, { passive: false });
  let drag = null;
  mapCanvas.addEventListener("mousedown", (e) => { drag = canvasPoint(e); });
  window.addEventListener("mouseup", () => { drag = null; });
  mapCanvas.addEventListener("mousemove", (e) => {
    if (!drag) return;
    const p = canvasPoint(e);
    fit.x += p[0] - drag[0];
    fit.y += p[1] - drag[1];
    drag = p;
    drawMap();
  });
  mapCanvas.addEventListener("dblclick", () => { fitMap(); drawMap(); });
  // A global-frame point to canvas pixels (image row 0 is the largest y).
  function toMap(x, y) {
    const ix = (x - M.origin[0]) / M.resolution;
    const iy = M.height - (y - M.origin[1]) / M.resolution;
    return [fit.x + ix * fit.s, fit.y + iy * fit.s];
  }
  document.getElementById("map-note").textContent =
    "(" + (M.width * M.resolution).toFixed(0) + " x " + (M.height * M.resolution).toFixed(0) +
    " m, the final estimate; wheel: zoom, drag: pan, double click: fit)";

  const areas = D.areas || [];
  const areaPose = {};
  for (const a of areas) if (a.pose) areaPose[a.id] = a.pose;
  const stepArea = D.step_area || [];

  function drawRobot(ctx, p, size, colour) {
    const c = Math.cos(p[2]), s = Math.sin(p[2]);
    ctx.save();
    ctx.translate(p[0], p[1]);
    ctx.beginPath();
    // The heading on the canvas: y points down, so the angle's sign flips.
    ctx.moveTo(size * c, -size * s);
    ctx.lineTo(-size * 0.6 * c + size * 0.5 * s, size * 0.6 * s + size * 0.5 * c);
    ctx.lineTo(-size * 0.6 * c - size * 0.5 * s, size * 0.6 * s - size * 0.5 * c);
    ctx.closePath();
    ctx.fillStyle = colour;
    ctx.fill();
    ctx.lineWidth = 1;
    ctx.strokeStyle = "#000";
    ctx.stroke();
    ctx.restore();
  }

  function drawMap() {
    const ctx = mapCtx;
    ctx.fillStyle = "#cdcdcd";
    ctx.fillRect(0, 0, mapCanvas.width, mapCanvas.height);
    ctx.imageSmoothingEnabled = fit.s < 1;  // crisp cells when zoomed in
    if (mapReady) ctx.drawImage(mapImage, fit.x, fit.y, M.width * fit.s, M.height * fit.s);
    const now = first + cur;
    // Arcs between the areas created so far.
    ctx.setLineDash([4, 3]);
    ctx.strokeStyle = "rgba(60,60,60,0.7)";
    ctx.lineWidth = 1;
    for (const arc of D.arcs || []) {
      const a = areas.find((x) => x.id === arc.from), b = areas.find((x) => x.id === arc.to);
      if (!a || !b || !a.pose || !b.pose || a.created_step > now || b.created_step > now) continue;
      const p = toMap(a.pose[0], a.pose[1]), q = toMap(b.pose[0], b.pose[1]);
      ctx.beginPath();
      ctx.moveTo(p[0], p[1]);
      ctx.lineTo(q[0], q[1]);
      ctx.stroke();
    }
    ctx.setLineDash([]);
    // The trajectory up to the step, coloured by the area it was in.
    ctx.lineWidth = 2;
    let i = 0;
    while (i < cur) {
      const a = stepArea[i] || 0;
      ctx.strokeStyle = a ? areaColour(a) : "#555";
      ctx.beginPath();
      let p = toMap(traj[i][0], traj[i][1]);
      ctx.moveTo(p[0], p[1]);
      let j = i + 1;
      for (; j <= cur; ++j) {
        p = toMap(traj[j][0], traj[j][1]);
        ctx.lineTo(p[0], p[1]);
        if ((stepArea[j] || 0) !== a) break;
      }
      ctx.stroke();
      i = j;
    }
    // The areas created so far: their origins, labelled.
    ctx.font = "bold 12px DejaVu Sans, sans-serif";
    ctx.textBaseline = "middle";
    ctx.textAlign = "center";
    for (const a of areas) {
      if (!a.pose || a.created_step > now) continue;
      const p = toMap(a.pose[0], a.pose[1]);
      ctx.beginPath();
      ctx.arc(p[0], p[1], 8, 0, 2 * Math.PI);
      ctx.fillStyle = "rgba(255,255,255,0.85)";
      ctx.fill();
      ctx.lineWidth = 2;
      ctx.strokeStyle = areaColour(a.id);
      ctx.stroke();
      ctx.fillStyle = "#000";
      ctx.fillText(String(a.id), p[0], p[1] + 0.5);
    }
    const r = traj[cur];
    const p = toMap(r[0], r[1]);
    drawRobot(ctx, [p[0], p[1], r[2]], 9, "#ffd700");
  }
  mapImage.onload = () => {
    mapReady = true;
    render();
    document.body.dataset.report = errors.textContent ? "error" : "ready";
  };
  mapImage.onerror = () => fail("the map image " + M.image + " did not load");
  mapImage.src = M.image;

  // ---- plots over the steps ---------------------------------------------
  const PAD = { left: 38, right: 34, top: 8, bottom: 22 };
  function plotBox(canvas) {
    return { x0: PAD.left, x1: canvas.width - PAD.right, y0: PAD.top, y1: canvas.height - PAD.bottom };
  }
  const stepX = (box, i) => box.x0 + (n === 1 ? 0 : (i / (n - 1)) * (box.x1 - box.x0));
  const xStep = (box, x) => ((x - box.x0) / (box.x1 - box.x0)) * (n - 1);

  function axes(ctx, box, yTicks, yLabel, rightTicks) {
    ctx.strokeStyle = "#888";
    ctx.lineWidth = 1;
    ctx.strokeRect(box.x0 + 0.5, box.y0 + 0.5, box.x1 - box.x0, box.y1 - box.y0);
    ctx.fillStyle = "#333";
    ctx.font = "10px DejaVu Sans, sans-serif";
    ctx.textAlign = "right";
    ctx.textBaseline = "middle";
    for (const [v, y] of yTicks) ctx.fillText(v, box.x0 - 3, y);
    ctx.textAlign = "left";
    for (const [v, y] of rightTicks || []) ctx.fillText(v, box.x1 + 3, y);
    ctx.textAlign = "center";
    ctx.textBaseline = "top";
    for (let k = 0; k <= 4; ++k) {
      const i = Math.round((k * (n - 1)) / 4);
      ctx.fillText(String(first + i), stepX(box, i), box.y1 + 3);
    }
    ctx.save();
    ctx.translate(9, (box.y0 + box.y1) / 2);
    ctx.rotate(-Math.PI / 2);
    ctx.textBaseline = "middle";
    ctx.fillText(yLabel, 0, 0);
    ctx.restore();
  }

  // Each plot is drawn once offscreen; a step redraws it with its cursor.
  function offscreen(canvas, draw) {
    const off = document.createElement("canvas");
    off.width = canvas.width;
    off.height = canvas.height;
    draw(off.getContext("2d"), plotBox(canvas));
    return off;
  }
  function withCursor(canvas, background) {
    const ctx = canvas.getContext("2d");
    ctx.clearRect(0, 0, canvas.width, canvas.height);
    ctx.drawImage(background, 0, 0);
    const box = plotBox(canvas);
    const x = Math.round(stepX(box, cur)) + 0.5;
    ctx.strokeStyle = "#000";
    ctx.lineWidth = 1;
    ctx.beginPath();
    ctx.moveTo(x, box.y0);
    ctx.lineTo(x, box.y1);
    ctx.stroke();
  }
  function clickToStep(canvas) {
    canvas.addEventListener("click", (e) => {
      const r = canvas.getBoundingClientRect();
      setStep(xStep(plotBox(canvas), ((e.clientX - r.left) * canvas.width) / r.width));
    });
  }

  // P(current area): bands stacked by area id, one column of pixels per
  // step (or per the step under it, when there are more steps than pixels).
  const pmfCanvas = document.getElementById("pmf");
  const peak = {};
  for (const s of steps) for (const [a, p] of s.pmf) peak[a] = Math.max(peak[a] || 0, p);
  const pmfAreas = Object.keys(peak).map(Number).sort((a, b) => a - b);
  const pmfBackground = offscreen(pmfCanvas, (ctx, box) => {
    const h = box.y1 - box.y0;
    const columns = Math.max(1, Math.round(box.x1 - box.x0));
    const w = (box.x1 - box.x0) / Math.min(columns, n);
    for (let c = 0; c < Math.min(columns, n); ++c) {
      const i = Math.min(n - 1, Math.floor(((c + 0.5) * n) / Math.min(columns, n)));
      let y = box.y1;
      for (const [a, p] of steps[i].pmf) {
        ctx.fillStyle = areaColour(a);
        ctx.fillRect(box.x0 + c * w, y - p * h, w + 0.6, p * h);
        y -= p * h;
      }
    }
    // Loop-closure candidates: a tick at their steps along the top.
    ctx.fillStyle = "#000";
    for (const ev of D.events || [])
      if (ev.outcomes.some((o) => o.area !== null && o.probability >= 0.01))
        ctx.fillRect(Math.round(stepX(box, ev.step - first)) - 1, box.y0, 2, 5);
    // Accepted closures: a green tick along the bottom at their acceptance.
    ctx.fillStyle = "#0a0";
    for (const c of D.closures || [])
      ctx.fillRect(Math.round(stepX(box, c.accepted_step - first)) - 1, box.y1 - 6, 3, 6);
    axes(ctx, box, [["1", box.y0], ["0.5", (box.y0 + box.y1) / 2], ["0", box.y1]], "P(area)");
  });
  clickToStep(pmfCanvas);
  const legend = document.getElementById("pmf-legend");
  const shownAreas = pmfAreas.filter((a) => peak[a] > 0.05);
  for (const a of shownAreas.slice(0, 30)) {
    const key = document.createElement("span");
    key.className = "key";
    key.style.background = areaColour(a);
    legend.appendChild(key);
    legend.appendChild(document.createTextNode(String(a)));
  }
  if (shownAreas.length > 30) legend.appendChild(document.createTextNode(" ... " + (shownAreas.length - 30) + " more"));
  legend.appendChild(document.createTextNode(
    "  (area ids; ticks: black on top, loop-closure candidates; green below, closures accepted)"));

  // ESS of the most probable hypothesis, its particles, hypotheses alive.
  const essCanvas = document.getElementById("ess");
  const essMax = Math.max(1, ...steps.map((s) => Math.max(s.ess, s.particles)));
  const hypMax = Math.max(1, ...steps.map((s) => s.hypotheses));
  const essBackground = offscreen(essCanvas, (ctx, box) => {
    const h = box.y1 - box.y0;
    const line = (value, colour, dash, stepped) => {
      ctx.strokeStyle = colour;
      ctx.setLineDash(dash);
      ctx.lineWidth = 1.3;
      ctx.beginPath();
      for (let i = 0; i < n; ++i) {
        const x = stepX(box, i), y = box.y1 - value(steps[i]) * h;
        if (i === 0) ctx.moveTo(x, y);
        else {
          if (stepped) ctx.lineTo(x, box.y1 - value(steps[i - 1]) * h);
          ctx.lineTo(x, y);
        }
      }
      ctx.stroke();
      ctx.setLineDash([]);
    };
    line((s) => s.hypotheses / (hypMax * 1.1), "#9467bd", [], true);
    line((s) => s.particles / (essMax * 1.05), "#555", [4, 3], true);
    line((s) => s.ess / (essMax * 1.05), "#1f77b4", [], false);
    const top = essMax * 1.05;
    axes(ctx, box, [[top.toFixed(0), box.y0], [(top / 2).toFixed(0), (box.y0 + box.y1) / 2], ["0", box.y1]],
      "ESS", [[String(hypMax), box.y1 - h / 1.1], ["0", box.y1]]);
  });
  clickToStep(essCanvas);

  // ---- loop-closure candidates ------------------------------------------
  // The new-area events at which a known area was weighed.
  const candidates = (D.events || []).filter((ev) => ev.outcomes.some((o) => o.area !== null));
  // The closures TLCA accepted, by what they were made of: the step, the
  // area left and the known area entered (hypotheses that made the same
  // closure at one step share it).
  const accepted = {};
  for (const c of D.closures || []) accepted[c.step + ":" + c.from + ":" + c.to] = c;
  const acceptedOf = (ev, o) => accepted[ev.step + ":" + ev.from_area + ":" + o.area];
  const eventsDiv = document.getElementById("events");
  const rows = [];
  if (candidates.length === 0) {
    eventsDiv.textContent = "No new-area event weighed a known area: no loop closure was considered.";
  } else {
    const table = document.createElement("table");
    table.innerHTML = "<tr><th>step</th><th>hypothesis (P)</th><th>left area</th>" +
      "<th>P(new area)</th><th>known areas: P (&#10003; accepted at)</th></tr>";
    candidates.forEach((ev, k) => {
      const tr = document.createElement("tr");
      tr.className = "event";
      const pNew = ev.outcomes.filter((o) => o.area === null).reduce((t, o) => t + o.probability, 0);
      const known = ev.outcomes.filter((o) => o.area !== null);
      const best = Math.max(pNew, ...known.map((o) => o.probability));
      const cell = (text, win) => "<td" + (win ? ' class="win"' : "") + ">" + text + "</td>";
      tr.innerHTML = cell(String(ev.step)) + cell(ev.hypothesis + " (" + fmtP(ev.hypothesis_probability) + ")") +
        cell(String(ev.from_area)) + cell(fmtP(pNew), pNew === best) +
        "<td>" + known.map((o) => (o.probability === best ? "<b>" : "") + "area " + o.area + ": " +
          fmtP(o.probability) + (o.probability === best ? "</b>" : "") +
          (acceptedOf(ev, o) ? ' <span class="accepted">&#10003; ' + acceptedOf(ev, o).accepted_step + "</span>" : "")
        ).join(", ") + "</td>";
      tr.addEventListener("click", () => {
        selectEvent(k);
        setStep(ev.step - first);
      });
      table.appendChild(tr);
      rows.push(tr);
    });
    eventsDiv.appendChild(table);
  }

  const viewImages = {};
  function gridImage(src) {
    if (!viewImages[src]) {
      const img = new Image();
      img.onerror = () => fail("the candidate area image " + src + " did not load");
      img.src = src;
      viewImages[src] = img;
    }
    return viewImages[src];
  }

  // The observations (robot frame) placed at `pose`: global points.
  function place(points, pose) {
    const c = Math.cos(pose[2]), s = Math.sin(pose[2]);
    return points.map((p) => [pose[0] + c * p[0] - s * p[1], pose[1] + s * p[0] + c * p[1]]);
  }
  // The window both pictures of a candidate share, centred between the two
  // robot poses: as far as the nearer half of the observations reaches (4 to
  // 15 m), so the two compare at one scale, zoomed enough to see how far
  // apart the walls fall.
  function viewWindow(points, poses) {
    const d = points.map((p) => Math.hypot(p[0], p[1])).sort((a, b) => a - b);
    const r = Math.max(4, Math.min(15, (d.length ? d[Math.floor(d.length / 2)] : 0) + 1));
    const cx = (poses[0][0] + poses[1][0]) / 2, cy = (poses[0][1] + poses[1][1]) / 2;
    return { x0: cx - r, y0: cy - r, x1: cx + r, y1: cy + r };
  }

  // The candidate area's grid in `win`, the placed observations in red over
  // it, the robot in gold.
  function drawView(canvas, grid, world, pose, win) {
    const ctx = canvas.getContext("2d");
    const img = gridImage(grid.image);
    const paint = () => {
      const k = Math.min(canvas.width / (win.x1 - win.x0), canvas.height / (win.y1 - win.y0));
      const ox = (canvas.width - (win.x1 - win.x0) * k) / 2;
      const oy = (canvas.height - (win.y1 - win.y0) * k) / 2;
      const to = (x, y) => [ox + (x - win.x0) * k, oy + (win.y1 - y) * k];
      ctx.fillStyle = "#cdcdcd";
      ctx.fillRect(0, 0, canvas.width, canvas.height);
      const g = to(grid.origin[0], grid.origin[1] + grid.height * grid.resolution);
      ctx.imageSmoothingEnabled = false;
      ctx.drawImage(img, g[0], g[1], grid.width * grid.resolution * k, grid.height * grid.resolution * k);
      ctx.fillStyle = "rgba(220,0,0,0.75)";
      for (const [x, y] of world) {
        const q = to(x, y);
        ctx.fillRect(q[0] - 1.25, q[1] - 1.25, 2.5, 2.5);
      }
      const r = to(pose[0], pose[1]);
      drawRobot(ctx, [r[0], r[1], pose[2]], 9, "#ffd700");
      // A scale bar: 1 m.
      ctx.fillStyle = "#000";
      ctx.fillRect(8, canvas.height - 10, k, 3);
      ctx.font = "10px DejaVu Sans, sans-serif";
      ctx.textAlign = "left";
      ctx.textBaseline = "bottom";
      ctx.fillText("1 m", 8, canvas.height - 12);
    };
    if (img.complete && img.naturalWidth > 0) paint();
    else img.addEventListener("load", paint);
  }

  function figure(title, caption) {
    const f = document.createElement("figure");
    const canvas = document.createElement("canvas");
    canvas.width = 360;
    canvas.height = 300;
    const h = document.createElement("figcaption");
    h.innerHTML = "<b>" + title + "</b><br>" + caption;
    f.appendChild(canvas);
    f.appendChild(h);
    return [f, canvas];
  }

  let shown = -1;  // the candidate event drawn below, an index into candidates
  const views = document.getElementById("event-views");
  function selectEvent(k) {
    shown = k;
    rows.forEach((tr, j) => tr.classList.toggle("selected", j === k));
    // Its row into view within the list (not by scrolling the page).
    const tr = rows[k];
    if (tr.offsetTop < eventsDiv.scrollTop + 20 ||
        tr.offsetTop > eventsDiv.scrollTop + eventsDiv.clientHeight - 20)
      eventsDiv.scrollTop = tr.offsetTop - eventsDiv.clientHeight / 2;
    const ev = candidates[k];
    views.innerHTML = "";
    const pNew = ev.outcomes.filter((o) => o.area === null).reduce((t, o) => t + o.probability, 0);
    document.getElementById("event-title").textContent =
      "Loop-closure candidates at step " + ev.step + " (hypothesis " + ev.hypothesis + ", leaving area " + ev.from_area + ")";
    document.getElementById("event-text").textContent =
      "TSBI weighed 'a new area' (P " + isP(pNew) + ") against each known area below. Each is drawn twice: " +
      "the new area's observations (red) over the known area's grid at TSBI's best match (the loop closure), " +
      "and at the pose the arcs predict without a closure (the new-area reading). Robot in gold.";
    for (const o of ev.outcomes) {
      if (o.area === null) continue;
      const c = acceptedOf(ev, o);
      const stats = "P " + isP(o.probability) + ", log F = " + fmt(o.log_f, 2) +
        ", match ratio " + fmt(o.match_ratio, 2) + (o.child !== null ? ", became hypothesis " + o.child : ", not followed") +
        (c ? "; the closure " + ev.from_area + " - " + o.area + " made here was accepted at step " + c.accepted_step +
          " (" + (c.aligned ? "fine-aligned" : "not aligned") + ", " + (c.consistent ? "consistent" : "inconsistent") + ")" : "");
      if (!o.grid || !ev.points) {
        const p = document.createElement("p");
        p.textContent = "Area " + o.area + ": " + stats + " (no view recorded)";
        views.appendChild(p);
        continue;
      }
      const [f1, c1] = figure("Area " + o.area + " again: at the best match", stats);
      const d = Math.hypot(o.match[0] - o.prior[0], o.match[1] - o.prior[1]);
      const [f2, c2] = figure("A new area: at the pose the arcs predict in area " + o.area,
        "the match moved it by " + d.toFixed(2) + " m and " +
        (Math.abs(Math.atan2(Math.sin(o.match[2] - o.prior[2]), Math.cos(o.match[2] - o.prior[2]))) * 180 / Math.PI).toFixed(1) +
        " deg; P(new area) " + isP(pNew));
      views.appendChild(f1);
      views.appendChild(f2);
      const atMatch = place(ev.points, o.match), atPrior = place(ev.points, o.prior);
      const win = viewWindow(ev.points, [o.match, o.prior]);
      drawView(c1, o.grid, atMatch, o.match, win);
      drawView(c2, o.grid, atPrior, o.prior, win);
    }
  }

  // The event drawn below follows the step: the last one at or before it
  // (of those at one step, the one the reader clicked stays).
  function followStep() {
    const now = first + cur;
    let k = -1;
    candidates.forEach((ev, j) => { if (ev.step <= now) k = j; });
    if (k >= 0 && shown >= 0 && candidates[shown].step === candidates[k].step) return;
    if (k >= 0) {
      selectEvent(k);
      return;
    }
    shown = -1;
    rows.forEach((tr) => tr.classList.remove("selected"));
    views.innerHTML = "";
    document.getElementById("event-title").textContent = "No loop-closure candidate up to step " + now;
    document.getElementById("event-text").textContent =
      "The first known area weighed at a new-area event is at step " + candidates[0].step + ".";
  }
  if (candidates.length === 0) document.getElementById("event-detail").style.display = "none";

  // ---- one step ---------------------------------------------------------
  function render() {
    const s = steps[cur];
    const area = stepArea[cur] || 0;
    const pArea = (s.pmf.find(([a]) => a === area) || [0, 0])[1];
    readout.textContent = "step " + (first + cur) + " / " + (first + n - 1) + "  t = " +
      fmt(s.time - steps[0].time, 1) + " s  | area " + area + " (P " + fmt(pArea, 3) + ")  | ESS " +
      fmt(s.ess, 1) + " / " + s.particles + "  | hypotheses " + s.hypotheses;
    drawMap();
    withCursor(pmfCanvas, pmfBackground);
    withCursor(essCanvas, essBackground);
    candidates.forEach((ev, k) => rows[k].classList.toggle("past", ev.step <= first + cur));
    if (candidates.length > 0) followStep();
  }
  render();
})();
