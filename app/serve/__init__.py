"""`frost serve`: the simulation thread and an HTTP + WebSocket server for phones
(docs/phone.md); the wire format is docs/protocol.md."""

# (here, so that the command line names them without loading the server)
DEFAULT_PORT = 8025
MAX_PAGES = 16  # pages connected at once
