"""Live views of a running controller: the pilot's web page and the Foxglove WebSocket server."""
