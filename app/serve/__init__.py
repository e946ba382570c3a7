"""`frost serve`: the simulation thread and an HTTP + WebSocket server for phones
(docs/phone.md); the wire format is docs/protocol.md."""
