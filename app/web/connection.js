// The page's socket to `frost serve`: opened at once, opened again after a loss (waiting
// longer each time), and given up for good when the server refuses the page. What comes
// before the page can draw waits, in order, until it can.

const RETRY_FIRST = 250, RETRY_MOST = 8000;  // ms between reconnects: doubling up to this
const ASK_MS = 5000;  // at most this long for /meta's answer when a socket failed (refusal)
// Close codes of a server that refuses the page's socket (a policy, a size, a token).
const REFUSED = [1008, 1009, 4403];
// What the page says, and then does nothing more, when the server refuses its token.
const TOKEN_REPLACED = "this page's link (its token) was replaced: scan the new QR code";

export class Connection {
  // token: the page's ?token= (or null); query: "?token=..." or ""; status: the StatusLine.
  constructor(token, query, status) {
    this.token = token;
    this.query = query;
    this.status = status;
    this.socket = null;
    this.retry = null;    // the timer of the next try, while one waits
    this.stopped = false;  // no more tries: refused, or the page cannot draw
    this.early = [];      // [socket, event] of what came before the page could draw
    this.answered = false;  // the server answered /meta when the socket last failed to open
    this.onMessage = null;      // (socket, event) of each message, once the page can draw
    this.onClosed = () => {};   // the socket closed: nothing is in sync any more
    // The socket failed to open, and the server did not refuse the page (`answered`: it
    // answered /meta); true where the page goes on without it (the phone's own frost).
    this.onUnreachable = (_answered) => false;
  }

  connect(retry = RETRY_FIRST) {
    this.retry = null;
    const url = new URL("ws" + this.query, location.href);
    url.protocol = location.protocol === "https:" ? "wss:" : "ws:";
    const ws = new WebSocket(url);
    ws.binaryType = "arraybuffer";
    this.socket = ws;
    let opened = false;
    ws.onopen = () => { retry = RETRY_FIRST; opened = true; };
    ws.onmessage = (event) => {
      if (this.early) this.early.push([ws, event]);
      else this.onMessage(ws, event);
    };
    ws.onclose = async (event) => {
      this.onClosed();
      this.socket = null;
      if (this.stopped) return;
      if (await this.closed(event, opened)) return;
      this.retry = setTimeout(() => this.connect(Math.min(retry * 2, RETRY_MOST)), retry);
    };
  }

  // What a closed socket means, said in the status line; true where the page stops trying.
  async closed(event, opened) {
    if (REFUSED.includes(event.code)) {
      this.status.say(`refused: ${event.reason || event.code}`);
    } else if (!opened && !event.reason) {  // gone or refused (a browser does not say which)
      const why = await this.refusal();
      if (why) {
        this.refuse(why);
        return true;
      }
      if (this.stopped) return true;  // (no WebGL2, found meanwhile)
      this.status.say("frost serve is not reachable: trying again");  // (the page may have opened from the cache)
      if (this.onUnreachable(this.answered)) return true;
    } else {
      this.status.say(`reconnecting (${event.reason || "connection lost"})`);
    }
    return false;
  }

  // The messages that came while the page got ready, from the socket open now (a closed
  // one's are gone); from now on each goes to onMessage as it comes.
  ready(onMessage) {
    this.onMessage = onMessage;
    const early = this.early;
    this.early = null;
    for (const [ws, event] of early) {
      if (ws === this.socket) onMessage(ws, event);
    }
  }

  // `socket`, a stand-in with a WebSocket's send, close, readyState and onmessage (the
  // phone's own frost, alone.js), takes the socket's place: its messages go where the
  // socket's would, waiting as theirs until the page can draw.
  adopt(socket) {
    this.socket = socket;
    socket.onmessage = (event) => {
      if (this.early) this.early.push([socket, event]);
      else this.onMessage(socket, event);
    };
  }

  send(message) {
    const ws = this.socket;
    if (ws && ws.readyState === WebSocket.OPEN) ws.send(JSON.stringify(message));
  }

  // No more tries: the page cannot draw (`reason`, the socket's close reason).
  stop(reason) {
    this.stopped = true;
    this.early = null;
    if (this.socket) this.socket.close(1000, reason);
  }

  // Why the server refuses this page, or null (no answer, or it lets the page in). A socket
  // refused (403: the token was replaced, `frost serve --new-token`) fails as one to a server
  // that is gone, 1006 and no reason, so /meta is asked: the server refuses it alike.
  async refusal() {
    let r;
    this.answered = false;
    try {
      const signal = AbortSignal.timeout ? AbortSignal.timeout(ASK_MS) : undefined;
      r = await fetch(`meta${this.query}`, { cache: "no-store", signal });
    } catch {
      return null;  // not reachable
    }
    this.answered = true;
    if (r.status !== 403) return null;
    if (this.token) return TOKEN_REPLACED;
    // No token: the server says why (a token in force now, a name not this machine's).
    const line = await r.text().then((t) => t.split("\n")[0].replace(/^frost: /, ""), () => "");
    return (line || "frost serve refused this page (HTTP 403)").slice(0, 160);
  }

  // The server refuses this page for good: the status line says why from now on, and the page
  // neither retries nor says anything else (a new address is needed, not a new try).
  refuse(why) {
    this.status.refuse(why);
    this.stopped = true;
    console.warn(`frost: ${why}`);
  }
}
