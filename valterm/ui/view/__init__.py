"""The model view: the braille wireframe of robot and cell (``model_view``, a Textual widget
drawing what ``core.render.raster`` rasterises; poses are paced by ``ui.playback``).
"""
