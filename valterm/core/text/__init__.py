"""Text the core gives to every edge: the transcript lines of events (app, ``valterm run``, tests)."""
