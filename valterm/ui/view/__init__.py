"""The model view: the braille wireframe of robot and cell (raster, clock, widget).

``raster`` and ``clock`` are pure Python/numpy; ``model_view`` and ``animation`` are Textual.
"""
