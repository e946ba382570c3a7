// The page's status line: a word on what the page is doing, a notice that goes after a
// while, what it says at rest (the phone's own frost), and, once the server refused the
// page, the reason alone from then on.

const NOTICE_MS = 4000;

export class StatusLine {
  constructor(element) {
    this.element = element;
    this.refused = null;  // why the server refused the page, said instead of anything else
    this.resting = "";    // what the line says when it has nothing else to say ("on this phone")
    this.timer = 0;
  }

  get text() {
    return this.element.textContent;
  }

  say(text) {
    this.element.textContent = this.refused || text || this.resting;
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
