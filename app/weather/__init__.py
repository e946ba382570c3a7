"""The weather outside, read while frost runs (docs/method.md section 12, docs/command-line.md):
the client of Open-Meteo's geocoding and forecast APIs (`client`), the last good reading
kept in the user's config folder (`kept`), and the feed that asks beside the window or
the server and hands each reading on (`feed`)."""

# (here, so that the command line names them without loading aiohttp)
FORECAST_API = "https://api.open-meteo.com"
GEOCODING_API = "https://geocoding-api.open-meteo.com"
EVERY_MIN = 15.0  # minutes between readings
LEAST_EVERY_MIN = 5.0  # the API's data changes every 15 minutes: no need to ask more often
