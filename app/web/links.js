// Deep links (docs/phone.md, Deep links): `?preset=NAME` opens the page on that preset, and
// `?weather=here` or `?weather=LAT,LON` on the weather there, as the menu's choices would
// set them: to share a look, and for tests. A value the page cannot take is one line in
// the status line; the rest of the page opens as it would without it.

const NUMBER = /^[+-]?(\d+(\.\d*)?|\.\d+)$/;
const SHOWN = 24;  // characters of a bad value said back

// A value as the status line says it back: printable, short.
function said(value) {
  const clean = value.replace(/[^\x20-\x7e]/g, "?");
  return clean.length > SHOWN ? `${clean.slice(0, SHOWN)}…` : clean;
}

// `?weather=`'s place as weather_local.js's startWeather takes it: "here", or {latitude,
// longitude} (degrees); else {problem}: why not.
export function weatherSpec(value) {
  if (value === "here") return "here";
  const parts = value.split(",");
  if (parts.length === 2 && parts.every((p) => NUMBER.test(p.trim()))) {
    const [latitude, longitude] = parts.map((p) => Number(p.trim()));
    if (Math.abs(latitude) <= 90 && Math.abs(longitude) <= 180) return { latitude, longitude };
  }
  return { problem: `?weather=${said(value)} is not a place: here, or LAT,LON in degrees (such as 59.33,18.07)` };
}

// The links of a page's address (its `location.search`).
export class DeepLinks {
  constructor(search) {
    const query = new URLSearchParams(search);
    this.preset = query.get("preset");  // the preset asked for, or null
    this.weather = null;  // the weather asked for: "here" or {latitude, longitude}
    this.problems = [];   // what the page could not take, said on the first hello
    this.applied = false;
    const weather = query.get("weather");
    if (weather !== null) {
      const spec = weatherSpec(weather);
      if (spec.problem) this.problems.push(spec.problem);
      else this.weather = spec;
    }
  }

  // The first hello (the server's or the phone's own frost): the preset asked for, sent as
  // the menu sends it where the frost shows another (the server's frost, or a preset the
  // phone's own cannot start with, which then says why), and what could not be taken said.
  hello(hello, send, say) {
    if (this.applied) return;
    this.applied = true;
    const names = hello.presets || [];
    if (this.preset !== null && !names.includes(this.preset)) {
      this.problems.unshift(`?preset=${said(this.preset)} is no preset: one of ${names.join(", ")}`);
    } else if (this.preset !== null && hello.preset !== this.preset) {
      send({ type: "preset", name: this.preset });
    }
    if (this.problems.length) say(this.problems.join("; "));
  }
}
