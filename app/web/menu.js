// The page's small menu: preset, look, backdrop, warm finger, pause, clear, screenshot.
// Choices go to the server (which tells every page what changed); the menu shows its state.

import { backdropLabels } from "./photo.js";

export class Menu {
  constructor(root, send, screenshot) {
    this.root = root;
    this.send = send;
    this.pointers = null;
    const $ = (id) => root.querySelector(`#${id}`);
    this.panel = $("panel");
    $("open").addEventListener("click", (e) => {
      this.panel.hidden = !this.panel.hidden;
      // Closed: the keys go to the frost again, not to the menu's button left focused.
      if (this.panel.hidden) e.currentTarget.blur();
    });
    for (const kind of ["preset", "look", "backdrop"]) {
      $(kind).addEventListener("change", (e) => send({ type: kind, name: e.target.value }));
    }
    $("pause").addEventListener("click", () => send({ type: "pause" }));
    $("clear").addEventListener("click", () => send({ type: "clear" }));
    $("shot").addEventListener("click", () => screenshot());
    $("warm").addEventListener("change", (e) => { if (this.pointers) this.pointers.warm = e.target.checked; });
    this.$ = $;
  }

  // The server's state (hello / state messages merged).
  show(hello) {
    const lists = { preset: hello.presets, look: hello.looks, backdrop: hello.backdrops };
    for (const [kind, names] of Object.entries(lists)) {
      const select = this.$(kind);
      const wanted = (names || []).join("\n");
      if (select.dataset.names !== wanted) {
        const labels = kind === "backdrop" ? backdropLabels(names || []) : names || [];
        select.replaceChildren(...(names || []).map((n, i) => new Option(labels[i], n)));
        select.dataset.names = wanted;
      }
      if (hello[kind] !== undefined) select.value = hello[kind];
    }
    this.$("pause").textContent = hello.paused ? "Resume" : "Pause";
  }
}
