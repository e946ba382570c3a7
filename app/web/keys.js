// The keyboard: a key goes to the server by its GLFW name, as the desktop window's would;
// S or F12 takes the page's own screenshot instead.

// A key as GLFW names it (app/keys.py), or null.
export function keyName(event) {
  const code = event.code;
  if (/^Key[A-Z]$/.test(code)) return code.slice(3);
  if (/^Digit[0-9]$/.test(code)) return code.slice(5);
  if (/^F[0-9]+$/.test(code)) return code;
  const named = {
    Space: "SPACE", Period: "PERIOD", Equal: "EQUAL", Minus: "MINUS", NumpadAdd: "KP_ADD",
    NumpadSubtract: "KP_SUBTRACT", BracketLeft: "LEFT_BRACKET", BracketRight: "RIGHT_BRACKET",
    Quote: "APOSTROPHE", Semicolon: "SEMICOLON", ArrowLeft: "LEFT", ArrowRight: "RIGHT",
    ArrowUp: "UP", ArrowDown: "DOWN", Tab: "TAB", Escape: "ESCAPE",
  };
  return named[code] || null;
}

// The page's keys, from now on: each sent with send(message), or screenshot() taken.
export function listenToKeys(send, screenshot) {
  addEventListener("keydown", (event) => {
    if (event.target.closest && event.target.closest("#menu")) return;
    if (event.ctrlKey || event.metaKey || event.altKey) return;
    const name = keyName(event);
    if (!name) return;
    event.preventDefault();
    if (name === "S" || name === "F12") return void screenshot();
    send({ type: "key", key: name });
  });
}
