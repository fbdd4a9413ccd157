"""Name resolution, in parts; :mod:`cyphy.lang.resolve` is its entry point."""
