"""The command line: one function per command, each parsing, calling the API and formatting."""

from hdselect.cli.main import main

__all__ = ["main"]
