"""Checks of the viewers' options, shared by the Python API (`record`, `ViewerApp`,
`explain_node`) and the CLI. Each takes the name to report: the Python argument by default,
the CLI passes its option (`--depth`, `--node`, ...). Errors are ValueErrors naming it."""

from __future__ import annotations

import socket

import numpy as np

from conecull.datasets.checks import is_int

MAX_DEPTH = 64


def check_depth(value, name: str = "bvh_depth") -> int:
    """The BVH depth whose boxes are drawn."""
    if not is_int(value) or not 0 <= value <= MAX_DEPTH:
        raise ValueError(f"{name}: expected a BVH depth in [0, {MAX_DEPTH}], got {value!r}")
    return int(value)


def check_method(value, ccd: bool = False, name: str = "method") -> str:
    import conecull

    if ccd and value in conecull.METHODS and value not in conecull.CCD_METHODS:
        raise ValueError(f"{name}: {value!r} is a discrete (DCD) method; CCD needs one of "
                         f"{', '.join(conecull.CCD_METHODS)}")
    if not isinstance(value, str) or value not in conecull.METHODS:
        raise ValueError(f"{name}: expected one of {', '.join(conecull.METHODS)}, got {value!r}")
    return value


def check_compare(value, ccd: bool = False, name: str = "compare") -> tuple[str, ...]:
    """Methods to run beside a recording's own (record's compare=): None or a sequence of
    distinct method names, each valid for the query kind."""
    if value is None:
        return ()
    if isinstance(value, str) or not hasattr(value, "__iter__"):
        raise ValueError(f"{name}: expected a list of method names, got {value!r}")
    out = tuple(value)
    for m in out:
        check_method(m, ccd, name)
    dup = sorted({m for m in out if out.count(m) > 1})
    if dup:
        raise ValueError(f"{name}: {', '.join(map(repr, dup))} given twice")
    return out


def check_arithmetic(value, name: str = "arithmetic") -> str:
    import conecull

    if not isinstance(value, str) or value not in conecull.ARITHMETIC:
        raise ValueError(f"{name}: expected one of {', '.join(conecull.ARITHMETIC)}, got {value!r}")
    return value


def check_flag(value, name: str) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name}: expected True or False, got {value!r}")
    return bool(value)


def check_frame_range(value, n_frames: int, name: str = "frame_range") -> range | list[int]:
    """Frame indices, each in [0, n_frames): none negative (Python's 'from the end' would record
    another frame than asked) and none beyond the input (no silent clamping); at least one."""
    if value is None:
        return range(n_frames)
    have = f"the input has frames 0..{n_frames - 1}"
    if isinstance(value, range):  # checked by its ends: range(10**9) is not listed
        if len(value) == 0:
            raise ValueError(f"{name}: {value} selects no frame; {have}")
        for k in (value[0], value[-1]):
            if not 0 <= k < n_frames:
                raise ValueError(f"{name}: {value} reaches frame {k}, out of range: {have}")
        return value
    if isinstance(value, (str, bytes)) or not hasattr(value, "__iter__"):
        raise ValueError(f"{name}: expected frame indices such as range(2, 5) or [0, 3], got {value!r}")
    ks = list(value)
    if not ks:
        raise ValueError(f"{name}: selects no frame; {have}")
    for k in ks:
        if not is_int(k):
            raise ValueError(f"{name}: expected integer frame indices, got {k!r}")
        if not 0 <= k < n_frames:
            raise ValueError(f"{name}: frame {k} is out of range: {have}")
    return [int(k) for k in ks]


def check_node(value, n_nodes: int, name: str = "node") -> int:
    """A BVH node id of a collider that has n_nodes nodes."""
    if n_nodes == 0:
        raise ValueError(f"{name}: the collider has no BVH yet: run a query (col.dcd(V)) first")
    if not is_int(value):
        raise ValueError(f"{name}: expected an integer node id in 0..{n_nodes - 1}, got {value!r}")
    if not 0 <= value < n_nodes:
        raise ValueError(f"{name}: {value} is out of range: the BVH has nodes 0..{n_nodes - 1}")
    return int(value)


def check_face(value, n_faces: int, name: str = "face") -> int:
    """A triangle id of a mesh with n_faces triangles."""
    if not is_int(value):
        raise ValueError(f"{name}: expected an integer triangle id in 0..{n_faces - 1}, got {value!r}")
    if not 0 <= value < n_faces:
        raise ValueError(f"{name}: {value} is out of range: the mesh has triangles 0..{n_faces - 1}")
    return int(value)


def check_limit(value, name: str = "limit", none_ok: bool = False) -> int | None:
    """How many items to show: an integer >= 1 (None: all, where allowed). Not a slice bound: -1
    would silently drop the last item, and 0 print a heading with nothing under it."""
    if value is None and none_ok:
        return None
    if not is_int(value) or value < 1:
        raise ValueError(f"{name}: expected an integer >= 1{' or None (all)' if none_ok else ''}, got {value!r}")
    return int(value)


def check_host_port(host, port, host_name: str = "host", port_name: str = "port") -> None:
    """Refuse, before the viewer starts, what it cannot serve: its server starts in a thread
    that on such an error dies or retries for ever, while the caller waits for it."""
    if not is_int(port) or not 0 <= port <= 65535:
        raise ValueError(f"{port_name}: expected a TCP port in [0, 65535] (0: any free one), got {port!r}")
    if not isinstance(host, str) or not host:
        raise ValueError(f"{host_name}: expected a host name or IP address, got {host!r}")
    try:
        infos = socket.getaddrinfo(host, 0, type=socket.SOCK_STREAM, flags=socket.AI_PASSIVE)
    except (socket.gaierror, UnicodeError) as e:
        raise ValueError(f"{host_name}: cannot resolve {host!r} ({e})") from None
    # The server listens on the addresses the host names that it can bind (asyncio skips address
    # families the kernel lacks, e.g. IPv6 for 'localhost'): one is enough.
    errors = []
    for family, kind, proto, _, addr in infos:
        try:
            with socket.socket(family, kind, proto) as s:
                s.bind(addr)  # port 0: tests the address, whatever ports are taken
            return
        except OSError as e:
            errors.append(f"{addr[0]}: {e.strerror or e}")
    raise ValueError(f"{host_name}: cannot listen on {host!r} ({'; '.join(errors) or 'no address'}); "
                     "give an address of this machine, such as 127.0.0.1")


def url_host(host: str) -> str:
    """The host to put in a URL to open: wildcard addresses mean this machine; IPv6 in brackets."""
    if host in ("0.0.0.0", "::"):
        return "127.0.0.1" if host == "0.0.0.0" else "[::1]"
    return f"[{host}]" if ":" in host else host
