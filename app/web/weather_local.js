// The weather on the phone itself (issue 57, item 4): the page asks the weather API of the
// static site's config (site.js's `weather_api`) and grows the frost by it. For now the
// request is recorded where the page and its tests read it: `frost.local.weatherRequest`,
// `{here: true}` or `{latitude, longitude}` (a `?weather=` deep link, links.js). It stays
// there as the phone's own frost replaces `frost.local` (alone.js keeps what others put on it).
export function startWeather(spec) {
  const frost = window.frost;
  frost.local = { ...(frost.local || {}), weatherRequest: spec };
}
