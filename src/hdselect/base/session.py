"""One run of the command line: SIGTERM as an interrupt, any terminal, warnings held.

- SIGTERM (what ``timeout`` and job schedulers send) unwinds the run like Ctrl-C,
  so every temporary is removed on the way out.
- A terminal that cannot show a character (``PYTHONIOENCODING=ascii``) gets it
  replaced, never a UnicodeEncodeError.
- Warnings are held until the command succeeds: a refused input stays one line.
"""

from __future__ import annotations

import logging
import signal
import sys

EXIT_INTERRUPTED, EXIT_TERMINATED = 130, 143
"""Exit statuses of a run ended by Ctrl-C (SIGINT) and by SIGTERM: 128 + the signal."""


class Terminated(BaseException):
    """SIGTERM arrived: unwinds like Ctrl-C, so every temporary is removed on the way out."""


def _raise_terminated(signum: int, frame: object) -> None:
    raise Terminated()


def handle_sigterm():
    """Make SIGTERM unwind like Ctrl-C (main thread only); returns the handler it replaced."""
    try:
        return signal.signal(signal.SIGTERM, _raise_terminated)
    except ValueError:  # not the main thread
        return None


def tolerate_encoding() -> None:
    """Never fail on a terminal that cannot show a character: replace it instead."""
    for stream in (sys.stdout, sys.stderr):
        try:
            "▶²†─µ±".encode(stream.encoding or "ascii")
        except (UnicodeEncodeError, LookupError):
            reconfigure = getattr(stream, "reconfigure", None)
            if reconfigure is not None:
                reconfigure(errors="replace")


class HeldLog(logging.Handler):
    """Warnings held until the command succeeds, so an error stays one line (``-v``: live)."""

    def __init__(self, logger: logging.Logger) -> None:
        super().__init__(level=logging.INFO)
        self.logger = logger
        self.records: list[logging.LogRecord] = []
        self.verbose = False
        self.level_before = logger.level
        self.setFormatter(logging.Formatter("hdselect: %(levelname)s: %(message)s"))

    def start(self, verbose: bool) -> None:
        """Hold the logger's records from now on (print them at once when `verbose`)."""
        self.verbose = verbose
        self.logger.addHandler(self)
        self.logger.setLevel(logging.INFO if verbose else logging.WARNING)

    def emit(self, record: logging.LogRecord) -> None:
        """Hold a record, or print it at once when verbose."""
        if self.verbose:
            print(self.format(record), file=sys.stderr)
        else:
            self.records.append(record)

    def shown(self, loggers: tuple[str, ...]) -> None:
        """Drop what these loggers said: the command's output shows it already."""
        self.records = [r for r in self.records
                        if r.levelno > logging.WARNING or r.name not in loggers]

    def publish(self) -> None:
        """Print the held records (the command succeeded)."""
        for record in self.records:
            print(self.format(record), file=sys.stderr)
        self.records.clear()

    def stop(self) -> None:
        """Drop what is held (the command failed) and detach from the logger."""
        self.records.clear()
        self.logger.removeHandler(self)
        self.logger.setLevel(self.level_before)
