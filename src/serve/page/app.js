// kansei's pen page: Pointer Events in (every coalesced sample, with pressure and tilt), the
// samples streamed to /v1/stream while the pen moves, the fitted log-aesthetic chain drawn as it
// grows and at pen-up. The API is described in docs/service.md; this script uses only it.
"use strict";

(() => {
  const STORAGE_KEY = "kansei.pen-page.v1";
  const UNITS = "px";
  // Colours of the α map, as the SVG and PNG exports draw them (src/export/svg.rs).
  const ALPHA_BLUE = [33, 102, 172], ALPHA_ZERO = [128, 128, 128], ALPHA_RED = [178, 24, 43];
  const ALPHA_BLUE_END = -2, ALPHA_RED_END = 2;

  const $ = (id) => document.getElementById(id);
  const canvas = $("ink");
  const ctx = canvas.getContext("2d");
  const ui = {
    tolerance: $("tolerance"), continuity: $("continuity"), close: $("close"),
    alphaMode: $("alpha-mode"),
    alphaMin: $("alpha-min"), alphaMax: $("alpha-max"), alphaFixed: $("alpha-fixed"),
    comb: $("show-comb"), markers: $("show-markers"), ink: $("show-ink"),
    undo: $("undo"), redo: $("redo"), clear: $("clear"), hint: $("hint"),
    pen: $("pen"), message: $("message"),
  };

  // A stroke: {samples: [...], fit: {curves, dots, errors} | null, pending: bool}.
  const state = { strokes: [], redo: [], live: null, preview: null };
  // What tests and other scripts may read: the last final fit document (of one stroke, as
  // /v1/fit answers for that stroke alone), that stroke's kansei-stroke file, and counters.
  const api = {
    lastFit: null, lastStroke: null, finals: 0, previews: 0, errors: [],
    drawingFit: null, state,
    strokeFile: () => strokeFile(state.strokes),
  };
  window.kansei = api;
  // Script errors too, so that a test sees them.
  window.addEventListener("error", (e) => api.errors.push(`script: ${e.message}`));

  // ---------------------------------------------------------------- settings and storage --

  function settings() {
    return {
      tolerance: parseFloat(ui.tolerance.value),
      continuity: ui.continuity.value,
      close: ui.close.value,
      alphaMode: ui.alphaMode.value,
      alphaMin: parseFloat(ui.alphaMin.value),
      alphaMax: parseFloat(ui.alphaMax.value),
      alphaFixed: parseFloat(ui.alphaFixed.value),
      comb: ui.comb.checked, markers: ui.markers.checked, ink: ui.ink.checked,
    };
  }

  function applySettings(s) {
    if (!s) return;
    // No tolerance saved (auto) leaves the field empty: each stroke's own.
    ui.tolerance.value = Number.isFinite(s.tolerance) && s.tolerance > 0 ? s.tolerance : "";
    if (["g1", "g2", "c3"].includes(s.continuity)) ui.continuity.value = s.continuity;
    if (s.close === "auto" || s.close === "never") ui.close.value = s.close;
    if (s.alphaMode) ui.alphaMode.value = s.alphaMode;
    if (Number.isFinite(s.alphaMin)) ui.alphaMin.value = s.alphaMin;
    if (Number.isFinite(s.alphaMax)) ui.alphaMax.value = s.alphaMax;
    if (Number.isFinite(s.alphaFixed)) ui.alphaFixed.value = s.alphaFixed;
    ui.comb.checked = !!s.comb;
    ui.markers.checked = s.markers !== false;
    ui.ink.checked = s.ink !== false;
  }

  // The fit options as query parameters (the command line's names).
  function fitQuery() {
    const s = settings();
    const q = new URLSearchParams();
    if (Number.isFinite(s.tolerance) && s.tolerance > 0) q.set("tolerance", s.tolerance);
    q.set("continuity", s.continuity);
    q.set("close", s.close);
    if (s.alphaMode === "fixed" && Number.isFinite(s.alphaFixed)) {
      q.set("alpha", s.alphaFixed);
    } else if (Number.isFinite(s.alphaMin) && Number.isFinite(s.alphaMax) && s.alphaMin <= s.alphaMax) {
      q.set("alpha_range", `${s.alphaMin}:${s.alphaMax}`);
    }
    return q;
  }

  function strokeFile(strokes) {
    return {
      format: "kansei-stroke", version: 1, units: UNITS, source: "kansei pen page",
      strokes: strokes.map((s) => ({ samples: s.samples })),
    };
  }

  function save() {
    const doc = {
      settings: settings(),
      strokes: state.strokes.filter((s) => !s.pending).map((s) => ({ samples: s.samples, fit: s.fit })),
    };
    try {
      localStorage.setItem(STORAGE_KEY, JSON.stringify(doc));
    } catch (e) {
      say(`the drawing could not be kept for a reload: ${e.message}`, true);
    }
  }

  function load() {
    let doc = null;
    try {
      doc = JSON.parse(localStorage.getItem(STORAGE_KEY) || "null");
    } catch (e) {
      doc = null;
    }
    if (!doc) return;
    applySettings(doc.settings);
    state.strokes = (doc.strokes || [])
      .filter((s) => Array.isArray(s.samples) && s.samples.length > 0)
      .map((s) => ({ samples: s.samples, fit: s.fit || null, pending: false }));
    if (state.strokes.some((s) => !s.fit)) refitAll();
  }

  // ------------------------------------------------------------------------- messages --

  function say(text, error) {
    ui.message.textContent = text;
    ui.message.className = error ? "error" : "";
  }

  function summary() {
    const n = state.strokes.length;
    let segments = 0;
    for (const s of state.strokes) {
      for (const c of (s.fit && s.fit.curves) || []) segments += c.segments.length;
    }
    return n === 0 ? "ready" : `${n} stroke${n === 1 ? "" : "s"}, ${segments} LAC segment${segments === 1 ? "" : "s"}`;
  }

  // -------------------------------------------------------------------------- fitting --

  async function postFit(file, path = "/v1/fit", extra = {}) {
    const q = fitQuery();
    for (const [k, v] of Object.entries(extra)) q.set(k, v);
    const response = await fetch(`${path}?${q}`, {
      method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(file),
    });
    if (!response.ok) {
      let message = `${response.status}`;
      try { message = (await response.json()).error; } catch (e) { /* not JSON */ }
      throw new Error(message);
    }
    return response;
  }

  // Splits a document of several strokes into each stroke's part.
  function splitFit(doc, count) {
    const parts = Array.from({ length: count }, () => ({ curves: [], dots: [], errors: [] }));
    for (const c of doc.curves || []) if (parts[c.stroke]) parts[c.stroke].curves.push(c);
    for (const d of doc.dots || []) if (parts[d.stroke]) parts[d.stroke].dots.push(d);
    for (const e of doc.errors || []) if (parts[e.stroke]) parts[e.stroke].errors.push(e);
    return parts;
  }

  let refitTimer = null;
  let refitGeneration = 0;
  function refitSoon() {
    clearTimeout(refitTimer);
    refitTimer = setTimeout(refitAll, 250);
  }

  // Fits the whole drawing again (settings changed, or a reload without fits).
  async function refitAll() {
    const strokes = state.strokes.filter((s) => !s.pending);
    const generation = ++refitGeneration;
    if (strokes.length === 0) { redraw(); return; }
    say("fitting…");
    try {
      const doc = await (await postFit(strokeFile(strokes))).json();
      if (generation !== refitGeneration) return;
      api.drawingFit = doc;
      splitFit(doc, strokes.length).forEach((part, i) => { strokes[i].fit = part; });
      save();
      say(summary());
    } catch (e) {
      say(`fit refused: ${e.message}`, true);
    }
    redraw();
  }

  // The stream: samples out as the pen moves, previews and final fits back.
  const stream = {
    ws: null, query: "", open: false, outbox: [], byNumber: [], ended: 0,

    ensure() {
      const query = fitQuery().toString() + "&units=" + UNITS;
      if (this.ws && this.query === query && this.ws.readyState <= 1) return;
      if (this.ws) this.close();
      this.query = query;
      this.byNumber = []; this.ended = 0; this.open = false; this.outbox = [];
      const url = `${location.protocol === "https:" ? "wss" : "ws"}://${location.host}/v1/stream?${query}`;
      let ws;
      try { ws = new WebSocket(url); } catch (e) { this.ws = null; return; }
      this.ws = ws;
      ws.onopen = () => {
        this.open = true;
        for (const m of this.outbox) ws.send(m);
        this.outbox = [];
        say(summary());
      };
      ws.onmessage = (event) => this.receive(JSON.parse(event.data));
      ws.onclose = () => {
        if (this.ws !== ws) return;
        this.ws = null; this.open = false;
        // Strokes still waiting for their final fit get it over HTTP.
        for (const s of this.byNumber) if (s && s.pending) fitOverHttp(s);
        this.byNumber = [];
      };
    },

    close() {
      const ws = this.ws;
      this.ws = null;
      if (ws) { ws.onclose = null; ws.close(); }
      for (const s of this.byNumber) if (s && s.pending) fitOverHttp(s);
      this.byNumber = [];
    },

    send(message) {
      const text = JSON.stringify(message);
      if (!this.ws) return false;
      if (this.open) this.ws.send(text); else this.outbox.push(text);
      return true;
    },

    receive(m) {
      const stroke = this.byNumber[m.stroke];
      if (m.type === "preview") {
        api.previews += 1;
        if (state.live && state.live.number === m.stroke) {
          state.preview = { curves: m.curve.curves || [], dots: m.curve.dots || [] };
          redraw();
        }
      } else if (m.type === "final") {
        if (stroke) finish(stroke, m.curve);
      } else if (m.type === "error") {
        api.errors.push(m.error);
        if (m.final && stroke) {
          reject(stroke, m.error);
        } else if (!m.final) {
          say(m.error, true);
        }
      }
    },
  };

  function finish(stroke, doc) {
    stroke.pending = false;
    stroke.fit = { curves: doc.curves || [], dots: doc.dots || [], errors: doc.errors || [] };
    api.lastFit = doc;
    api.lastStroke = strokeFile([stroke]);
    api.finals += 1;
    if (stroke.fit.errors.length > 0) {
      say(stroke.fit.errors.map((e) => e.message).join("; "), true);
    } else {
      say(summary());
    }
    save();
    redraw();
  }

  function reject(stroke, message) {
    const i = state.strokes.indexOf(stroke);
    if (i >= 0) state.strokes.splice(i, 1);
    say(`stroke refused: ${message}`, true);
    api.finals += 1;
    redraw();
  }

  async function fitOverHttp(stroke) {
    try {
      finish(stroke, await (await postFit(strokeFile([stroke]))).json());
    } catch (e) {
      reject(stroke, e.message);
    }
  }

  // ---------------------------------------------------------------------- the pen --

  function sampleOf(event, rect, last) {
    const s = { x: event.clientX - rect.left, y: event.clientY - rect.top };
    let t = event.timeStamp / 1000;
    if (last && last.t !== undefined && t < last.t) t = last.t;
    s.t = t;
    if (event.pointerType !== "mouse" || event.pressure > 0) {
      s.pressure = Math.min(1, Math.max(0, event.pressure));
    }
    if (event.pointerType === "pen") {
      s.tilt_x = event.tiltX || 0;
      s.tilt_y = event.tiltY || 0;
    }
    return s;
  }

  let pendingSamples = [];
  let flushScheduled = false;
  function flushSamples() {
    flushScheduled = false;
    if (pendingSamples.length === 0) return;
    stream.send({ type: "samples", samples: pendingSamples });
    pendingSamples = [];
  }

  function addSamples(events) {
    const live = state.live;
    const rect = canvas.getBoundingClientRect();
    for (const e of events) {
      const last = live.samples[live.samples.length - 1];
      const s = sampleOf(e, rect, last);
      if (!Number.isFinite(s.x) || !Number.isFinite(s.y)) continue;
      live.samples.push(s);
      pendingSamples.push(s);
    }
    const e = events[events.length - 1];
    if (e) {
      const parts = [e.pointerType];
      if (e.pointerType !== "mouse") parts.push(`pressure ${e.pressure.toFixed(2)}`);
      if (e.pointerType === "pen") parts.push(`tilt ${e.tiltX}°, ${e.tiltY}°`, `twist ${e.twist || 0}°`);
      ui.pen.textContent = `${parts.join(" · ")} · ${live.samples.length} samples`;
    }
    if (!flushScheduled) {
      flushScheduled = true;
      requestAnimationFrame(flushSamples);
    }
    redraw();
  }

  canvas.addEventListener("pointerdown", (e) => {
    if (state.live || (e.pointerType === "mouse" && e.button !== 0)) return;
    e.preventDefault();
    try { canvas.setPointerCapture(e.pointerId); } catch (err) { /* synthetic pointer */ }
    stream.ensure();
    const number = stream.ws ? stream.ended : null;
    state.live = { pointerId: e.pointerId, samples: [], number, pending: true, fit: null };
    state.preview = null;
    ui.hint.classList.add("hidden");
    addSamples([e]);
  });

  canvas.addEventListener("pointermove", (e) => {
    if (!state.live || e.pointerId !== state.live.pointerId) return;
    const events = typeof e.getCoalescedEvents === "function" ? e.getCoalescedEvents() : [];
    addSamples(events.length > 0 ? events : [e]);
  });

  function penUp(e) {
    if (!state.live || e.pointerId !== state.live.pointerId) return;
    const stroke = state.live;
    state.live = null;
    state.preview = null;
    flushSamples();
    if (stroke.samples.length === 0) { redraw(); return; }
    state.strokes.push(stroke);
    state.redo = [];
    const sent = stroke.number !== null && stream.ws && stream.send({ type: "end" });
    if (sent) {
      stream.byNumber[stroke.number] = stroke;
      stream.ended += 1;
    } else {
      if (stroke.number !== null && stream.ws) stream.ended += 1;
      fitOverHttp(stroke);
    }
    say("fitting…");
    redraw();
  }
  canvas.addEventListener("pointerup", penUp);
  canvas.addEventListener("pointercancel", (e) => {
    if (!state.live || e.pointerId !== state.live.pointerId) return;
    const stroke = state.live;
    state.live = null;
    state.preview = null;
    pendingSamples = [];
    if (stroke.number !== null && stream.send({ type: "cancel" })) stream.ended += 1;
    redraw();
  });

  // ------------------------------------------------------------------ LAC geometry --

  function alphaColour(alpha) {
    if (alpha === null || alpha === undefined || !Number.isFinite(alpha)) return "rgb(0,0,0)";
    const [end, t] = alpha < 0
      ? [ALPHA_BLUE, Math.min(1, alpha / ALPHA_BLUE_END)]
      : [ALPHA_RED, Math.min(1, alpha / ALPHA_RED_END)];
    const c = [0, 1, 2].map((i) => Math.round(ALPHA_ZERO[i] + t * (end[i] - ALPHA_ZERO[i])));
    return `rgb(${c[0]},${c[1]},${c[2]})`;
  }

  // Signed curvature at fraction u of a segment: a log-aesthetic curve has ρ^α linear in arc
  // length (ln ρ for α = 0), ρ = 1/|κ|; arcs and lines (α null) have constant curvature.
  function kappaAt(seg, u) {
    const k0 = seg.kappa0, k1 = seg.kappa1, a = seg.alpha;
    if (a === null || a === undefined || k0 === k1) return k0;
    const sign = k0 + k1 > 0 ? 1 : -1;
    const A = Math.abs(k0), B = Math.abs(k1);
    let m;
    if (a === 0) {
      m = Math.exp(Math.log(A) + (Math.log(B) - Math.log(A)) * u);
    } else {
      const p = -a; // |κ|^(−α) is linear in arc length
      const lin = Math.pow(A, p) + (Math.pow(B, p) - Math.pow(A, p)) * u;
      m = lin > 0 ? Math.pow(lin, 1 / p) : 0;
    }
    return sign * (Number.isFinite(m) ? m : 0);
  }

  // Points of a segment about `step` pixels apart: [x, y, θ, κ] each, integrated from the start
  // and corrected linearly onto the segment's recorded end.
  function segmentPoints(seg, step) {
    const turn = Math.abs(seg.theta1 - seg.theta0);
    const n = Math.min(4000, Math.max(8, Math.ceil(seg.length / step), Math.ceil(turn / 0.02)));
    const sub = 4, h = seg.length / (n * sub);
    const out = [[seg.start[0], seg.start[1], seg.theta0, kappaAt(seg, 0)]];
    let x = seg.start[0], y = seg.start[1], theta = seg.theta0, k = kappaAt(seg, 0);
    for (let i = 1; i <= n * sub; i++) {
      const u = i / (n * sub);
      const k1 = kappaAt(seg, u);
      const theta1 = theta + 0.5 * (k + k1) * h;
      const mid = theta + 0.25 * (k + k1) * h + (k - k1) * h / 8;
      x += Math.cos(mid) * h;
      y += Math.sin(mid) * h;
      theta = theta1; k = k1;
      if (i % sub === 0) out.push([x, y, theta, k]);
    }
    const dx = seg.end[0] - x, dy = seg.end[1] - y;
    for (let i = 0; i < out.length; i++) {
      const u = i / (out.length - 1);
      out[i][0] += dx * u;
      out[i][1] += dy * u;
    }
    return out;
  }

  // Cached per segment record.
  const pointsCache = new WeakMap();
  function pointsOf(seg) {
    let p = pointsCache.get(seg);
    if (!p) { p = segmentPoints(seg, 2); pointsCache.set(seg, p); }
    return p;
  }

  // ------------------------------------------------------------------------- drawing --

  let frameRequested = false;
  function redraw() {
    if (frameRequested) return;
    frameRequested = true;
    requestAnimationFrame(draw);
  }

  function resize() {
    const dpr = window.devicePixelRatio || 1;
    const r = canvas.getBoundingClientRect();
    canvas.width = Math.max(1, Math.round(r.width * dpr));
    canvas.height = Math.max(1, Math.round(r.height * dpr));
    redraw();
  }
  window.addEventListener("resize", resize);

  function drawInk(samples, colour) {
    if (samples.length === 0) return;
    ctx.strokeStyle = colour;
    ctx.fillStyle = colour;
    ctx.lineCap = "round";
    ctx.lineJoin = "round";
    if (samples.length === 1) {
      ctx.beginPath();
      ctx.arc(samples[0].x, samples[0].y, 1.5, 0, 2 * Math.PI);
      ctx.fill();
      return;
    }
    for (let i = 1; i < samples.length; i++) {
      const a = samples[i - 1], b = samples[i];
      const p = b.pressure === undefined ? 0.5 : b.pressure;
      ctx.lineWidth = 0.6 + 2.4 * p;
      ctx.beginPath();
      ctx.moveTo(a.x, a.y);
      ctx.lineTo(b.x, b.y);
      ctx.stroke();
    }
  }

  function combScale(fits) {
    let max = 0;
    for (const fit of fits) {
      for (const c of fit.curves) {
        for (const seg of c.segments) max = Math.max(max, Math.abs(seg.kappa0), Math.abs(seg.kappa1));
      }
    }
    return max > 0 ? 36 / max : 0;
  }

  function drawFit(fit, s, preview) {
    ctx.lineCap = "round";
    ctx.lineJoin = "round";
    for (const c of fit.curves) {
      if (s.comb) {
        const scale = combScale([fit]) || 0;
        ctx.lineWidth = 1;
        for (const seg of c.segments) {
          const pts = pointsOf(seg);
          ctx.strokeStyle = "rgba(120, 90, 200, 0.35)";
          ctx.beginPath();
          const every = Math.max(1, Math.round(pts.length / Math.max(2, seg.length / 6)));
          for (let i = 0; i < pts.length; i += every) {
            const [x, y, th, k] = pts[i];
            ctx.moveTo(x, y);
            ctx.lineTo(x + Math.sin(th) * k * scale, y - Math.cos(th) * k * scale);
          }
          ctx.stroke();
          ctx.strokeStyle = "rgba(120, 90, 200, 0.7)";
          ctx.beginPath();
          pts.forEach(([x, y, th, k], i) => {
            const px = x + Math.sin(th) * k * scale, py = y - Math.cos(th) * k * scale;
            if (i === 0) ctx.moveTo(px, py); else ctx.lineTo(px, py);
          });
          ctx.stroke();
        }
      }
      ctx.lineWidth = preview ? 2 : 2.6;
      ctx.globalAlpha = preview ? 0.75 : 1;
      for (const seg of c.segments) {
        const pts = pointsOf(seg);
        ctx.strokeStyle = alphaColour(seg.alpha);
        ctx.beginPath();
        pts.forEach(([x, y], i) => (i === 0 ? ctx.moveTo(x, y) : ctx.lineTo(x, y)));
        ctx.stroke();
      }
      ctx.globalAlpha = 1;
      if (s.markers && !preview) {
        for (const seg of c.segments.slice(1)) {
          ctx.fillStyle = "#ffffff";
          ctx.strokeStyle = "#3c4043";
          ctx.lineWidth = 1.2;
          ctx.beginPath();
          ctx.arc(seg.start[0], seg.start[1], 3, 0, 2 * Math.PI);
          ctx.fill();
          ctx.stroke();
        }
        for (const split of c.splits) drawSplit(split);
      }
    }
    for (const d of fit.dots || []) {
      ctx.fillStyle = "#202124";
      ctx.beginPath();
      ctx.arc(d.point[0], d.point[1], 2.5, 0, 2 * Math.PI);
      ctx.fill();
    }
  }

  function drawSplit(split) {
    const [x, y] = split.point;
    const r = 4.5;
    ctx.lineWidth = 1.5;
    ctx.beginPath();
    switch (split.kind) {
      case "inflection":
        ctx.strokeStyle = "#188038";
        ctx.moveTo(x, y - r); ctx.lineTo(x + r, y); ctx.lineTo(x, y + r); ctx.lineTo(x - r, y); ctx.closePath();
        break;
      case "curvature_extremum":
        ctx.strokeStyle = "#e37400";
        ctx.arc(x, y, r, 0, 2 * Math.PI);
        break;
      case "corner":
        ctx.strokeStyle = "#b3261e";
        ctx.rect(x - r, y - r, 2 * r, 2 * r);
        break;
      default:
        ctx.strokeStyle = "#5f6368";
        ctx.moveTo(x - r, y); ctx.lineTo(x + r, y); ctx.moveTo(x, y - r); ctx.lineTo(x, y + r);
    }
    ctx.stroke();
  }

  function draw() {
    frameRequested = false;
    const dpr = window.devicePixelRatio || 1;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.fillStyle = "#fbfaf7";
    ctx.fillRect(0, 0, canvas.width, canvas.height);
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    // A light dot grid, 20 px apart.
    ctx.fillStyle = "#e3e1da";
    const w = canvas.width / dpr, h = canvas.height / dpr;
    for (let x = 10; x < w; x += 20) for (let y = 10; y < h; y += 20) ctx.fillRect(x - 0.5, y - 0.5, 1, 1);
    const s = settings();
    for (const stroke of state.strokes) {
      if (s.ink || !stroke.fit) drawInk(stroke.samples, stroke.fit ? "rgba(60,64,67,0.22)" : "rgba(60,64,67,0.55)");
    }
    for (const stroke of state.strokes) if (stroke.fit) drawFit(stroke.fit, s, false);
    if (state.live) {
      drawInk(state.live.samples, "rgba(32,33,36,0.55)");
      if (state.preview) drawFit(state.preview, s, true);
    }
    ui.undo.disabled = state.strokes.length === 0;
    ui.redo.disabled = state.redo.length === 0;
    ui.clear.disabled = state.strokes.length === 0;
    ui.hint.classList.toggle("hidden", state.strokes.length > 0 || !!state.live);
  }

  // ------------------------------------------------------------------------- controls --

  function undo() {
    const s = state.strokes.pop();
    if (s) { state.redo.push([s]); save(); say(summary()); redraw(); }
  }
  function redo() {
    const group = state.redo.pop();
    if (group) { state.strokes.push(...group); save(); say(summary()); redraw(); }
  }
  ui.undo.addEventListener("click", undo);
  ui.redo.addEventListener("click", redo);
  ui.clear.addEventListener("click", () => {
    if (state.strokes.length === 0) return;
    state.redo.push(state.strokes.splice(0));
    save(); say(summary()); redraw();
  });
  window.addEventListener("keydown", (e) => {
    if (!(e.ctrlKey || e.metaKey) || e.target.tagName === "INPUT") return;
    const key = e.key.toLowerCase();
    if (key === "z" && !e.shiftKey) { e.preventDefault(); undo(); }
    else if ((key === "z" && e.shiftKey) || key === "y") { e.preventDefault(); redo(); }
  });

  function showAlphaInputs() {
    const fixed = ui.alphaMode.value === "fixed";
    ui.alphaFixed.hidden = !fixed;
    ui.alphaMin.hidden = fixed;
    ui.alphaMax.hidden = fixed;
  }
  for (const el of [ui.tolerance, ui.continuity, ui.close, ui.alphaMode, ui.alphaMin, ui.alphaMax, ui.alphaFixed]) {
    el.addEventListener("change", () => { showAlphaInputs(); save(); refitSoon(); });
  }
  for (const el of [ui.comb, ui.markers, ui.ink]) {
    el.addEventListener("change", () => { save(); redraw(); });
  }

  function saveBlob(blob, name) {
    const a = document.createElement("a");
    a.href = URL.createObjectURL(blob);
    a.download = name;
    document.body.appendChild(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(a.href), 10000);
  }

  document.querySelectorAll("[data-download]").forEach((button) => {
    button.addEventListener("click", async () => {
      const kind = button.dataset.download;
      const strokes = state.strokes.filter((s) => !s.pending);
      if (strokes.length === 0) { say("nothing drawn yet", true); return; }
      const file = strokeFile(strokes);
      if (kind === "strokes") {
        saveBlob(new Blob([JSON.stringify(file, null, 1)], { type: "application/json" }), "kansei.strokes.json");
        return;
      }
      const [path, name, extra] = {
        svg: ["/v1/export/svg", "kansei.svg", { layers: "alpha" }],
        dxf: ["/v1/export/dxf", "kansei.dxf", {}],
        png: ["/v1/export/png", "kansei.png", { layers: "samples,segments,splits,legend,scale-bar" }],
        json: ["/v1/fit", "kansei.curve.json", {}],
      }[kind];
      try {
        const response = await postFit(file, path, extra);
        saveBlob(await response.blob(), name);
        say(`${name} downloaded`);
      } catch (e) {
        say(`${kind.toUpperCase()} refused: ${e.message}`, true);
      }
    });
  });

  // -------------------------------------------------------------------------- start --

  load();
  showAlphaInputs();
  resize();
  fetch("/v1/health")
    .then((r) => r.json())
    .then((h) => say(`${summary()} · kansei ${h.version}`))
    .catch(() => say("the kansei service does not answer", true));
  stream.ensure();
  api.ready = true;
})();
