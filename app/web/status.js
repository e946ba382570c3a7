// The page's status line: a word on what the page is doing, a notice that goes after a
// while, what it says when nothing else is (the phone's own frost, the weather outside),
// and, once the server refused the page, the reason alone from then on.

const NOTICE_MS = 4000;

export class StatusLine {
  constructor(element) {
    this.element = element;
    this.refused = null;  // why the server refused the page, said instead of anything else
    this.resting = "";  // said when nothing else is: "on this phone" (the phone's own frost)
    this.idle = "";  // said when nothing else is: the weather's place and reading
    this.timer = 0;
  }

  get text() {
    return this.element.textContent;
  }

  say(text) {
    this.element.textContent = this.refused || text || this.atRest();
  }

  // What the line says when nothing else is: the phone's own frost, the weather, or both.
  atRest() {
    return [this.resting, this.idle].filter(Boolean).join(" · ");
  }

  // The line said when nothing else is (now, if nothing else is said).
  setIdle(text) {
    const showing = this.element.textContent === this.atRest();
    this.idle = text;
    if (showing) this.say("");
  }

  // `text` for a few seconds (a refused choice, a photo sent).
  notice(text) {
    this.say(text);
    clearTimeout(this.timer);
    this.timer = setTimeout(() => this.say(""), NOTICE_MS);
  }

  // The server refuses this page for good: its reason is all the line says from now on.
  refuse(why) {
    this.refused = why;
    this.say(why);
  }
}
