"""The weather outside, read while frost runs (docs/method.md section 11, docs/command-line.md):
the client of Open-Meteo's geocoding and forecast APIs (`client`), the last good reading
kept in the user's config folder (`kept`), and the feed that asks beside the window or
the server and hands each reading on (`feed`)."""
