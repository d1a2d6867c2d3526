"""The `cspace` command-line tool: a thin front end on the library's public API."""
