"""Levels at rest: the `kinetix-level/1` file format (parse, export, files on disk), the reference Kinetix format,
stored solutions, and generated level sets."""
