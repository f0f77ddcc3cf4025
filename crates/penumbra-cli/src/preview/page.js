"use strict";
// The preview page: the shared view (view.js), and the Stop button.
(() => {
  const stop = document.getElementById("stop");
  let stopping = false;
  const view = penumbraView({
    openStatus: () => (stopping ? ["stopping after this pass", "stopped"] : ["rendering", "rendering"]),
    end: () => { stop.disabled = true; },
  });
  stop.addEventListener("click", async () => {
    stop.disabled = true;
    try {
      const r = await fetch("/stop?" + view.query, { method: "POST", headers: { "X-Penumbra-Token": view.token } });
      if (r.ok) {
        stopping = true;
        view.setStatus("stopping after this pass", "stopped");
      } else {
        view.setStatus(`stop refused (${r.status})`, "lost");
        stop.disabled = false;
      }
    } catch (e) {
      view.setStatus("stop failed: " + e.message, "lost");
      stop.disabled = false;
    }
  });
})();
