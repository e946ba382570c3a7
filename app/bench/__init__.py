"""The benchmarks of the package (`frost bench sim|render`; the tiles', run as `python -m bench tiles`) and
what only they use: the scripted scribbles, the taps, the pane's and the fern's measures.
They print figures and assert nothing; app.cli runs them, and nothing else of the app
imports them. The ones that drive a browser or load the server with scripted pages are the
checkout's (bench/, `python -m bench`), outside the wheel."""
