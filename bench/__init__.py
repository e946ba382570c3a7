"""The checkout's benchmarks: the ones that drive a browser (the phone page against the
desktop, the page through `frost serve`, as a phone app, the clock), shape a network (the
shaping proxy) or load the server with scripted pages, and what only they use. Run them
from a checkout, `python -m bench page|serve|clock|shaper` (bench/__main__.py); they are not
in the wheel (pyproject.toml), and nothing of app/ or sim/ imports them."""
