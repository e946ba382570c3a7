// How the page was served. This file is frost serve's: the page has a server, which runs
// the frost, the weather and the photos. `frost web DIR` (app/tools/web_site.py) writes
// its own into the static site it builds: `static: true` (no server answers there, so the
// page grows its own frost at once and asks no server anything), the build's hash (its
// `version.json` says it too) and the weather APIs the page then asks itself.
export const SITE = { static: false, build: null, weather_api: null, geocoding_api: null };
