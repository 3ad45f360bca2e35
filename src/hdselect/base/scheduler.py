"""A Dask cluster: a LocalCluster here, or a scheduler's address checked before it is used.

Dask's client trusts its peer: it waits for the scheduler's greeting without a time
limit, and reads the first 8 bytes of any answer as a frame length (an HTTP server's
``HTTP/1.1`` becomes 3.5e18 bytes). So an address is checked in words first (scheme,
host, port 1 to 65535), then the peer is asked, within the time limit, for the greeting
every Dask scheduler sends on a new connection; only a peer that sends one is handed to
Dask.
"""

from __future__ import annotations

import logging
import math
import socket
import struct
import time
from typing import Any
from urllib.parse import urlsplit

from hdselect.base.errors import InputError

DASK_HINT = "pip install 'hdselect[dask]'"
"""How to install the optional Dask executor."""
DEFAULT_TIMEOUT = 30.0
"""How long connecting to a Dask scheduler may take by default [s]."""
MAX_TIMEOUT = 86400.0
"""The longest time limit accepted [s] (a day)."""
GREETING_BYTES = 1 << 16
"""The largest greeting taken from a scheduler [bytes]; Dask's is about 100."""
SCHEMES = ("tcp", "tls")
"""The address schemes of a Dask scheduler taken here."""


def scheduler_address(value: object, field: str) -> str:
    """``local``, or a scheduler's address ``tcp://HOST:PORT`` (or ``tls://``), checked.

    Args:
        value: What the user gave.
        field: The option or parameter that gave it, for the message.

    Returns:
        The address as given.

    Raises:
        InputError: Not ``local`` nor an address with a scheme, a host and a port from 1
            to 65535 (and nothing else).
    """
    wrong = InputError(f"expected 'local' or a scheduler address tcp://HOST:PORT (port 1 to "
                       f"65535), got {value!r}", field=field)
    if value == "local":
        return "local"
    if not isinstance(value, str):
        raise wrong
    try:
        parts = urlsplit(value)
        port = parts.port
        if parts.hostname:
            parts.hostname.encode("idna")  # a label of more than 63 characters is refused
    except ValueError as err:  # UnicodeError included
        raise wrong from err
    if (parts.scheme not in SCHEMES or not parts.hostname or port is None
            or not 1 <= port <= 65535 or parts.username is not None or parts.password
            or parts.path or parts.query or parts.fragment or not value.startswith(
                f"{parts.scheme}://")):
        raise wrong
    return value


def timeout_seconds(value: object, field: str) -> float:
    """A time limit for connecting, checked: more than 0 and at most a day [s].

    Raises:
        InputError: Not a number in (0, `MAX_TIMEOUT`].
    """
    if (isinstance(value, bool) or not isinstance(value, int | float)
            or not math.isfinite(value) or not 0.0 < value <= MAX_TIMEOUT):
        raise InputError(f"expected a time in seconds, more than 0 and at most "
                         f"{MAX_TIMEOUT:.0f}; got {value!r}", field=field)
    return float(value)


def probe(address: str, timeout: float, field: str) -> None:
    """Check that a Dask scheduler answers at `address` within `timeout` seconds.

    A ``tcp://`` peer must send Dask's greeting (a frame of at most `GREETING_BYTES`
    naming its pickle protocol); of a ``tls://`` peer, whose greeting is encrypted, only
    the connection is checked here (Dask's own time limit covers the rest).

    Args:
        address: A checked address (`scheduler_address`).
        timeout: The time limit [s].
        field: The option that gave the address, for the message.

    Raises:
        InputError: Nothing listens there, nothing answers in time, or the peer is not a
            Dask scheduler.
    """
    parts = urlsplit(address)
    deadline = time.monotonic() + timeout
    try:
        with socket.create_connection((parts.hostname, parts.port), timeout=timeout) as peer:
            if parts.scheme == "tls":
                return
            head = _read(peer, 8, deadline)
            (length,) = struct.unpack("<Q", head) if len(head) == 8 else (0,)
            body = _read(peer, length, deadline) if 16 <= length <= GREETING_BYTES else b""
    except TimeoutError as err:
        raise InputError(f"the Dask scheduler at {address} did not answer within "
                         f"{timeout:g} s", field=field) from err
    except OSError as err:
        raise InputError(f"cannot reach the Dask scheduler at {address} "
                         f"({err.strerror or err})", field=field) from err
    if b"pickle-protocol" not in body:
        first = head.split(b"\n")[0]
        raise InputError(f"{address} is not a Dask scheduler (it answered {first!r})",
                         field=field)


def _read(peer: socket.socket, count: int, deadline: float) -> bytes:
    """Exactly `count` bytes from the peer by the deadline (``time.monotonic``)."""
    data = bytearray()
    while len(data) < count:
        left = deadline - time.monotonic()
        if left <= 0.0:
            raise TimeoutError
        peer.settimeout(left)
        chunk = peer.recv(min(count - len(data), 1 << 16))
        if not chunk:
            break
        data += chunk
    return bytes(data)


def local_cluster(workers: int) -> Any:
    """A Dask LocalCluster on this machine: worker processes of one thread, on 127.0.0.1 only."""
    from distributed import LocalCluster

    return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                        host="127.0.0.1", dashboard_address=None, silence_logs=logging.ERROR)


def open_client(scheduler: str, workers: int, timeout: float, field: str) -> tuple[Any, Any]:
    """A Dask client, and the LocalCluster it runs on (None for a scheduler elsewhere).

    Args:
        scheduler: ``local`` for a LocalCluster of `workers` processes of one thread on
            127.0.0.1 only, else a scheduler's address (`scheduler_address`), probed first.
        workers: The LocalCluster's workers.
        timeout: The time limit of connecting [s] (`timeout_seconds`).
        field: The option that gave the scheduler, for the messages.

    Raises:
        InputError: Dask not installed, or no Dask scheduler answering there in time.
    """
    try:
        from distributed import Client
    except ImportError as err:
        raise InputError(f"needs Dask's distributed scheduler: {DASK_HINT}",
                         field=field) from err
    cluster = None
    if scheduler == "local":
        cluster = local_cluster(workers)
    else:
        probe(scheduler, timeout, field)
    try:
        client = Client(cluster if cluster is not None else scheduler, timeout=timeout)
    except (OSError, TimeoutError) as err:
        if cluster is not None:
            cluster.close()
        raise InputError(f"cannot reach the Dask scheduler ({err})", field=field) from err
    return client, cluster


def where(scheduler: str, workers: int) -> str:
    """Where a Dask cluster computes, in words."""
    if scheduler == "local":
        return f"a Dask LocalCluster of {workers} worker{'s' if workers > 1 else ''}"
    return f"the Dask scheduler at {scheduler}"
