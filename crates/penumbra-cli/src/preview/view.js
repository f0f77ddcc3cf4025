"use strict";
// What every live page shares: follows /events, fetches /image after each
// frame and tone-maps the linear floats here (exposure in stops, then the
// sRGB curve), with zoom, pan and the statistics table. A page's own script
// calls penumbraView(hooks), where hooks may hold:
//   drag(dx, dy, event): a drag over the image, in screen pixels since the
//     last call; return true to take it (else the image pans);
//   wheel(event): the wheel over the image; return true to take it (else
//     the image zooms);
//   frame(data), end(data): after the view has shown a `frame` or `end` event;
//   openStatus(): the [text, class] of the status once the stream is open.
// It returns { token, query, setStatus, isEnded }.
function penumbraView(hooks) {
  const token = new URLSearchParams(location.search).get("token") || "";
  const query = "token=" + encodeURIComponent(token);
  const $ = (id) => document.getElementById(id);
  const view = $("view");
  const canvas = $("image");
  const ctx = canvas.getContext("2d");
  const littleEndian = new Uint8Array(new Uint32Array([1]).buffer)[0] === 1;

  let floats = null; // linear RGB of the shown frame
  let width = 0;
  let height = 0;
  let pixels = null; // ImageData of the tone-mapped frame
  let exposure = 0;
  let zoom = 1;
  let panX = 0;
  let panY = 0;
  let fitted = true;
  let wantedSeq = 0;
  let shownSeq = 0;
  let fetching = false;
  let toneQueued = false;
  let ended = false;

  // ---- numbers ----
  const count = new Intl.NumberFormat("en-US");
  function duration(s) {
    if (s === null || s === undefined || !isFinite(s)) return "–";
    s = Math.max(0, Math.round(s));
    const h = Math.floor(s / 3600);
    const m = Math.floor((s % 3600) / 60);
    const sec = s % 60;
    const two = (n) => String(n).padStart(2, "0");
    return h > 0 ? `${h}h ${two(m)}m ${two(sec)}s` : m > 0 ? `${m}m ${two(sec)}s` : `${sec}s`;
  }
  function rate(r) {
    if (!isFinite(r) || r <= 0) return "–";
    const units = [[1e9, " G"], [1e6, " M"], [1e3, " k"]];
    for (const [u, name] of units) if (r >= u) return (r / u).toFixed(2) + name;
    return r.toFixed(0);
  }
  function cell(v) {
    if (typeof v === "number") return Number.isInteger(v) ? count.format(v) : v.toPrecision(4);
    return String(v);
  }

  // ---- status, progress, statistics ----
  function setStatus(text, kind) {
    const s = $("status");
    s.textContent = text;
    s.className = "status " + (kind || "");
  }
  function showProgress(d) {
    $("pass").textContent = `pass ${d.pass}/${d.passes}`;
    $("p-pass").textContent = `${d.pass} / ${d.passes}`;
    $("p-elapsed").textContent = duration(d.elapsed_s);
    $("p-eta").textContent = duration(d.eta_s);
    $("p-rays").textContent = count.format(d.rays);
    $("p-rate").textContent = rate(d.rays_per_s);
    $("p-size").textContent = `${d.width} × ${d.height}`;
    document.title = `${d.pass}/${d.passes} · penumbra preview`;
    showStats(d.stats);
  }
  function flatten(value, prefix, rows) {
    if (value !== null && typeof value === "object" && !Array.isArray(value)) {
      for (const [k, v] of Object.entries(value)) flatten(v, prefix ? `${prefix}.${k}` : k, rows);
    } else {
      rows.push([prefix, Array.isArray(value) ? value.map(cell).join(", ") : cell(value)]);
    }
    return rows;
  }
  function showStats(stats) {
    const table = $("stats");
    table.replaceChildren();
    if (stats === null || stats === undefined) return;
    for (const [name, text] of flatten(stats, "", [])) {
      const tr = table.insertRow();
      const th = document.createElement("th");
      th.textContent = name;
      tr.appendChild(th);
      tr.insertCell().textContent = text;
    }
  }

  // ---- image ----
  function srgb(v) {
    return v <= 0.0031308 ? 12.92 * v : 1.055 * Math.pow(v, 1 / 2.4) - 0.055;
  }
  function toneMap() {
    toneQueued = false;
    if (!floats) return;
    const scale = Math.pow(2, exposure);
    const out = pixels.data; // clamps to 0..255 and rounds; NaN becomes 0
    for (let i = 0, j = 0; i < floats.length; i += 3, j += 4) {
      out[j] = 255 * srgb(floats[i] * scale);
      out[j + 1] = 255 * srgb(floats[i + 1] * scale);
      out[j + 2] = 255 * srgb(floats[i + 2] * scale);
    }
    ctx.putImageData(pixels, 0, 0);
  }
  function queueToneMap() {
    if (!toneQueued) {
      toneQueued = true;
      requestAnimationFrame(toneMap);
    }
  }
  function decode(buffer) {
    const dv = new DataView(buffer);
    const magic = String.fromCharCode(...new Uint8Array(buffer, 0, Math.min(4, buffer.byteLength)));
    if (buffer.byteLength < 16 || magic !== "PNB1") throw new Error("not a preview image");
    const w = dv.getUint32(4, true);
    const h = dv.getUint32(8, true);
    const n = w * h * 3;
    if (buffer.byteLength !== 16 + 4 * n) throw new Error("truncated image");
    let f;
    if (littleEndian) {
      f = new Float32Array(buffer, 16, n);
    } else {
      f = new Float32Array(n);
      for (let i = 0; i < n; i++) f[i] = dv.getFloat32(16 + 4 * i, true);
    }
    if (w !== width || h !== height) {
      width = w;
      height = h;
      canvas.width = w;
      canvas.height = h;
      pixels = ctx.createImageData(w, h);
      for (let j = 3; j < pixels.data.length; j += 4) pixels.data[j] = 255;
      if (fitted) fit();
    }
    floats = f;
    toneMap();
  }
  async function loadImage() {
    if (fetching) return;
    fetching = true;
    try {
      while (shownSeq !== wantedSeq) {
        const target = wantedSeq;
        const r = await fetch("/image?" + query, { cache: "no-store" });
        if (r.status !== 200) break;
        decode(await r.arrayBuffer());
        shownSeq = target;
      }
    } catch (e) {
      if (!ended) setStatus("image: " + e.message, "lost");
    } finally {
      fetching = false;
    }
  }

  // ---- exposure ----
  const slider = $("exposure");
  function setExposure(v) {
    exposure = v;
    slider.value = v;
    $("exposure-value").textContent = (v >= 0 ? "+" : "") + v.toFixed(1);
    queueToneMap();
  }
  slider.addEventListener("input", () => setExposure(parseFloat(slider.value)));
  $("exposure-reset").addEventListener("click", () => setExposure(0));

  // ---- zoom and pan ----
  function applyView() {
    canvas.style.transform = `translate(${panX}px, ${panY}px) scale(${zoom})`;
    $("zoom-value").textContent = (zoom * 100).toFixed(zoom < 0.1 ? 1 : 0) + "%";
  }
  function fit() {
    const r = view.getBoundingClientRect();
    if (width === 0 || r.width === 0) return;
    zoom = Math.min(r.width / width, r.height / height);
    panX = (r.width - width * zoom) / 2;
    panY = (r.height - height * zoom) / 2;
    fitted = true;
    applyView();
  }
  function zoomAt(factor, x, y) {
    const next = Math.min(256, Math.max(1 / 64, zoom * factor));
    panX = x - ((x - panX) * next) / zoom;
    panY = y - ((y - panY) * next) / zoom;
    zoom = next;
    fitted = false;
    applyView();
  }
  function centre() {
    const r = view.getBoundingClientRect();
    return [r.width / 2, r.height / 2];
  }
  view.addEventListener("wheel", (e) => {
    e.preventDefault();
    if (hooks.wheel && hooks.wheel(e)) return;
    const r = view.getBoundingClientRect();
    zoomAt(e.deltaY < 0 ? 1.25 : 0.8, e.clientX - r.left, e.clientY - r.top);
  }, { passive: false });
  $("zoom-in").addEventListener("click", () => zoomAt(2, ...centre()));
  $("zoom-out").addEventListener("click", () => zoomAt(0.5, ...centre()));
  $("zoom-one").addEventListener("click", () => zoomAt(1 / zoom, ...centre()));
  $("zoom-fit").addEventListener("click", fit);
  window.addEventListener("resize", () => { if (fitted) fit(); });

  let drag = null;
  view.addEventListener("pointerdown", (e) => {
    drag = { x: e.clientX, y: e.clientY, panX, panY, lastX: e.clientX, lastY: e.clientY };
    view.setPointerCapture(e.pointerId);
    view.classList.add("dragging");
  });
  view.addEventListener("pointerup", () => { drag = null; view.classList.remove("dragging"); });
  view.addEventListener("pointermove", (e) => {
    if (drag && hooks.drag && hooks.drag(e.clientX - drag.lastX, e.clientY - drag.lastY, e)) {
      drag.lastX = e.clientX;
      drag.lastY = e.clientY;
    } else if (drag) {
      panX = drag.panX + e.clientX - drag.x;
      panY = drag.panY + e.clientY - drag.y;
      fitted = false;
      applyView();
    }
    const r = view.getBoundingClientRect();
    const px = Math.floor((e.clientX - r.left - panX) / zoom);
    const py = Math.floor((e.clientY - r.top - panY) / zoom);
    if (floats && px >= 0 && py >= 0 && px < width && py < height) {
      const i = 3 * (py * width + px);
      const rgb = [floats[i], floats[i + 1], floats[i + 2]].map((v) => v.toPrecision(3)).join(" ");
      $("p-pixel").textContent = `(${px}, ${py}) ${rgb}`;
    } else {
      $("p-pixel").textContent = "–";
    }
  });

  // ---- events ----
  const events = new EventSource("/events?" + query);
  events.addEventListener("open", () => {
    if (!ended) setStatus(...(hooks.openStatus ? hooks.openStatus() : ["rendering", "rendering"]));
  });
  events.addEventListener("frame", (e) => {
    const d = JSON.parse(e.data);
    showProgress(d);
    wantedSeq = d.seq;
    loadImage();
    if (hooks.frame) hooks.frame(d);
  });
  events.addEventListener("end", (e) => {
    const d = JSON.parse(e.data);
    ended = true;
    events.close();
    $("p-eta").textContent = "–";
    setStatus((d.stopped ? "stopped" : "finished") + (d.message ? ": " + d.message : ""),
      d.stopped ? "stopped" : "finished");
    if (hooks.end) hooks.end(d);
  });
  events.addEventListener("error", () => {
    if (ended) return;
    const closed = events.readyState === EventSource.CLOSED;
    setStatus(closed ? "disconnected" : "reconnecting", "lost");
  });

  setExposure(0);
  applyView();
  return { token, query, setStatus, isEnded: () => ended };
}
