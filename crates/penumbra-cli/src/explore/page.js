"use strict";
// The explorer's page: the shared view (view.js), the controls built from
// GET /schema, the scene list, and the camera moved by dragging (orbit) and
// the wheel (dolly).
(() => {
  const $ = (id) => document.getElementById(id);
  const message = $("message");
  let view = null;

  async function post(path, body) {
    try {
      const r = await fetch(path + "?" + view.query, {
        method: "POST",
        headers: { "Content-Type": "application/json", "X-Penumbra-Token": view.token },
        body: JSON.stringify(body),
      });
      const text = await r.text();
      message.textContent = r.ok ? "" : text;
      return r.ok ? JSON.parse(text) : null;
    } catch (e) {
      message.textContent = e.message;
      return null;
    }
  }

  // ---- controls, from the schema ----
  const inputs = {};
  function defaultText(d) {
    if (d !== null && typeof d === "object") return d.follows ? `as ${d.follows}` : d.computed;
    return String(d);
  }
  function control(c) {
    const label = document.createElement("label");
    label.textContent = c.name.replace(/_/g, " ");
    label.title = `${c.doc} [default: ${defaultText(c.default)}]`;
    let input;
    if (c.kind === "choice") {
      input = document.createElement("select");
      const scene = new Option(`(scene's; default ${defaultText(c.default)})`, "");
      input.add(scene);
      for (const name of c.choices) input.add(new Option(name, name));
    } else if (c.kind === "switch") {
      input = document.createElement("input");
      input.type = "checkbox";
      input.checked = c.default === true;
    } else {
      input = document.createElement("input");
      input.type = "number";
      if (c.min !== undefined) input.min = c.min;
      if (c.max !== undefined) input.max = c.max;
      input.step = c.kind === "int" ? 1 : "any";
      input.placeholder = defaultText(c.default);
    }
    input.id = "c-" + c.name;
    label.htmlFor = input.id;
    input.title = label.title;
    input.addEventListener("change", () => {
      let value;
      if (c.kind === "switch") value = input.checked;
      else if (input.value === "") return;
      else value = c.kind === "choice" ? input.value : Number(input.value);
      post("/set", { name: c.name, value });
    });
    inputs[c.name] = input;
    $("controls").append(label, input);
  }
  function showChosen(chosen) {
    for (const [name, value] of Object.entries(chosen || {})) {
      const input = inputs[name];
      if (!input || document.activeElement === input) continue;
      if (input.type === "checkbox") input.checked = value === true;
      else input.value = String(value);
    }
  }
  // The values in effect (the scene's, or chosen) where a control is not
  // set: as its placeholder, or its select's first entry.
  function showEffective(s) {
    if (!s) return;
    const effective = {
      integrator: s.integrator, width: s.width, height: s.height, spp: s.spp, passes: s.passes,
      pixel_distribution: s.pixel_distribution, lens_distribution: s.lens_distribution,
    };
    for (const effect of ["shadow", "reflection", "refraction"]) {
      if (!s[effect]) continue;
      effective[effect + "_rays"] = s[effect].rays;
      effective[effect + "_distribution"] = s[effect].distribution;
    }
    for (const [name, value] of Object.entries(effective)) {
      const input = inputs[name];
      if (!input || value === undefined) continue;
      if (input.tagName === "SELECT") input.options[0].text = `(in effect: ${value})`;
      else if (input.type !== "checkbox") input.placeholder = String(value);
    }
  }
  function showSettings(info) {
    const table = $("settings");
    table.replaceChildren();
    if (!info) return;
    const rows = [["run", info.run], ["scene", info.scene_name]];
    const walk = (v, prefix) => {
      if (v !== null && typeof v === "object" && !Array.isArray(v)) {
        for (const [k, w] of Object.entries(v)) walk(w, prefix ? `${prefix}.${k}` : k);
      } else rows.push([prefix, Array.isArray(v) ? v.map((x) => Number(x).toPrecision(4)).join(", ") : v]);
    };
    walk(info.settings, "");
    if (info.camera) walk(info.camera, "camera");
    for (const [k, v] of rows) {
      const tr = table.insertRow();
      const th = document.createElement("th");
      th.textContent = k;
      tr.appendChild(th);
      tr.insertCell().textContent = String(v);
    }
  }

  // ---- camera: drag orbits, wheel dollies; one request at a time ----
  let pending = { yaw: 0, pitch: 0, dolly: 1 };
  let sending = false;
  async function flushCamera() {
    if (sending) return;
    if (pending.yaw === 0 && pending.pitch === 0 && pending.dolly === 1) return;
    const move = pending;
    pending = { yaw: 0, pitch: 0, dolly: 1 };
    sending = true;
    await post("/camera", { orbit: [move.yaw, move.pitch], dolly: move.dolly });
    sending = false;
    flushCamera();
  }
  const DEGREES_PER_PIXEL = 0.3;
  function drag(dx, dy, e) {
    if (e.shiftKey) return false;
    pending.yaw += dx * DEGREES_PER_PIXEL;
    pending.pitch += dy * DEGREES_PER_PIXEL;
    flushCamera();
    return true;
  }
  function wheel(e) {
    if (e.ctrlKey) return false;
    pending.dolly *= e.deltaY < 0 ? 0.9 : 1 / 0.9;
    flushCamera();
    return true;
  }

  view = penumbraView({
    drag,
    wheel,
    frame: (d) => {
      if (d.info) {
        showChosen(d.info.chosen);
        showEffective(d.info.settings);
        showSettings(d.info);
        $("scene").value = String(d.info.scene);
      }
      if (d.pass === d.passes) view.setStatus("finished", "finished");
      else view.setStatus("rendering", "rendering");
    },
  });

  (async () => {
    const r = await fetch("/schema?" + view.query, { cache: "no-store" });
    if (!r.ok) {
      message.textContent = "schema: " + r.status;
      return;
    }
    const schema = await r.json();
    for (const c of schema.controls) control(c);
    const select = $("scene");
    for (const s of schema.scenes) {
      const o = new Option(s.name, String(s.index));
      if (s.description) o.title = s.description;
      select.add(o);
    }
    select.addEventListener("change", () => post("/scene", { scene: Number(select.value) }));
  })();
})();
