// The page's small menu: preset, look, backdrop, warm finger, pause, clear, screenshot.
// Choices go to the server (which tells every page what changed), or to the phone's own
// frost while it grows (its hello says `local`); the menu shows its state.

import { backdropLabels } from "./photo.js";

export class Menu {
  // saveSession(): the phone's own session downloaded; phoneKept(): whether the phone keeps
  // a frost of its own (growing, or waiting while the page shows the server's).
  constructor(root, send, screenshot, saveSession = () => {}, phoneKept = () => false) {
    this.root = root;
    this.send = send;
    this.phoneKept = phoneKept;
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
    $("session").addEventListener("click", () => saveSession());
    $("warm").addEventListener("change", (e) => { if (this.pointers) this.pointers.warm = e.target.checked; });
    this.$ = $;
  }

  // The server's state (hello / state messages merged).
  show(hello) {
    const lists = { preset: hello.presets, look: hello.looks, backdrop: hello.backdrops };
    for (const [kind, names] of Object.entries(lists)) {
      const select = this.$(kind);
      // On the phone's own frost, what it cannot grow is shown as frost serve's alone.
      const off = kind === "preset" && hello.local ? hello.server_only || [] : [];
      const wanted = (names || []).join("\n") + (off.length ? `\n${off}` : "");
      if (select.dataset.names !== wanted) {
        const labels = kind === "backdrop" ? backdropLabels(names || []) : names || [];
        select.replaceChildren(...(names || []).map((n, i) => {
          const option = new Option(off.includes(n) ? `${labels[i]} (needs frost serve)` : labels[i], n);
          option.disabled = off.includes(n);
          return option;
        }));
        select.dataset.names = wanted;
      }
      if (hello[kind] !== undefined) select.value = hello[kind];
    }
    this.$("pause").textContent = hello.paused ? "Resume" : "Pause";
    // The phone's own session (frost serve keeps its own session file): while its frost
    // grows, and after a join while it waits on the phone.
    const session = this.$("session");
    session.hidden = !(hello.local || this.phoneKept());
    session.textContent = hello.local ? "Save session" : "Save this phone's session";
  }
}
