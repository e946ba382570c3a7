// PNG text chunks (tEXt) written in the browser, so a screenshot carries the same
// metadata keys as the desktop's (app/images.py: frost_meta, png_writer).

const CRC_TABLE = (() => {
  const t = new Uint32Array(256);
  for (let n = 0; n < 256; n++) {
    let c = n;
    for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
    t[n] = c >>> 0;
  }
  return t;
})();

export function crc32(bytes) {
  let c = 0xffffffff;
  for (let i = 0; i < bytes.length; i++) c = CRC_TABLE[(c ^ bytes[i]) & 0xff] ^ (c >>> 8);
  return (c ^ 0xffffffff) >>> 0;
}

// JSON as Python's json.dumps writes it by default: ASCII only, ", " and ": " between items.
export function pyJson(value) {
  const ascii = (s) => s.replace(/[\u007f-\uffff]/g, (ch) => "\\u" + ch.charCodeAt(0).toString(16).padStart(4, "0"));
  if (value === null || value === undefined) return "null";
  if (Array.isArray(value)) return "[" + value.map(pyJson).join(", ") + "]";
  if (typeof value === "object") {
    return "{" + Object.entries(value).map(([k, v]) => ascii(JSON.stringify(k)) + ": " + pyJson(v)).join(", ") + "}";
  }
  if (typeof value === "number" && Number.isInteger(value) && !Object.is(value, -0)) return String(value);
  if (typeof value === "number") return pyFloat(value);
  return ascii(JSON.stringify(value));
}

// A float as Python's repr writes it: the shortest digits that read back (as JavaScript's),
// positional from 1e-4 to below 1e16 (1.0, not 1; 0.0001), else with an exponent of at least
// two digits and its sign (1e-05, 1.5e+16); a negative zero is -0.0.
function pyFloat(x) {
  if (!Number.isFinite(x)) return x > 0 ? "Infinity" : x < 0 ? "-Infinity" : "NaN";
  if (Object.is(x, -0)) return "-0.0";
  const [digits, power] = x.toExponential().split("e");
  const exponent = Number(power);
  if (exponent < -4 || exponent >= 16) {
    return `${digits}e${exponent < 0 ? "-" : "+"}${String(Math.abs(exponent)).padStart(2, "0")}`;
  }
  const s = String(x);  // positional in this range
  return s.includes(".") ? s : s + ".0";
}

function chunk(type, data) {
  const out = new Uint8Array(12 + data.length);
  const view = new DataView(out.buffer);
  view.setUint32(0, data.length);
  for (let i = 0; i < 4; i++) out[4 + i] = type.charCodeAt(i);
  out.set(data, 8);
  view.setUint32(8 + data.length, crc32(out.subarray(4, 8 + data.length)));
  return out;
}

function latin1(s) {
  const out = new Uint8Array(s.length);
  for (let i = 0; i < s.length; i++) out[i] = s.charCodeAt(i) & 0xff;
  return out;
}

// `png` (bytes) with a tEXt chunk for each entry of `meta` (JSON unless a string) after
// its header chunk.
export function withText(png, meta) {
  const ihdrEnd = 8 + 12 + new DataView(png.buffer, png.byteOffset).getUint32(8);
  const parts = [png.subarray(0, ihdrEnd)];
  for (const [key, value] of Object.entries(meta)) {
    const text = typeof value === "string" ? value : pyJson(value);
    const data = latin1(key + "\0" + text.replace(/[^\u0000-\u00ff]/g, "?"));
    parts.push(chunk("tEXt", data));
  }
  parts.push(png.subarray(ihdrEnd));
  const out = new Uint8Array(parts.reduce((n, p) => n + p.length, 0));
  let o = 0;
  for (const p of parts) { out.set(p, o); o += p.length; }
  return out;
}
