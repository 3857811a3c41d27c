"""Readers and writers of the workspace files (SPEC §5), one module each: ``setup``,
``locations``, ``programs``, ``datfiler``, ``variables``, ``vplus``; ``atomic`` writes and
``errors`` names what went wrong.

Every reader raises :class:`~valterm.core.files.errors.FileFormatError` (``NAME.SET:12:
reason``) for any malformed input and nothing else; every writer is atomic. The package
re-exports nothing: the app's first frame loads ``errors`` without the readers and numpy
(issue 25, the start).
"""
