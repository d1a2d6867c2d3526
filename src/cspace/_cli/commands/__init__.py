"""One module per `cspace` command."""
