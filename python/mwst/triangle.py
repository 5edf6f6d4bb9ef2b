"""mwst.triangle: a drop-in for the `triangle` package (in progress: needs the library's switch parser)."""
