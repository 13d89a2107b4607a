"""A delay relay in front of a lab robot's sshd: a realistic network without netem.

This kernel has no ``netem`` qdisc, so a lab robot's round trip is emulated in user space:
sshd listens on an inner address of the robot's own namespace (``127.0.0.1:2222``) and this
relay, running in the same namespace, listens on the robot's public address (``IP:22``).
The client sees the same address and the same host key (the bytes are passed through
unchanged); each chunk is delivered after the one-way delay (plus a random jitter), in
order, in both directions.

TCP's own handshake is answered by the relay's kernel at once, so the round trip it costs
on a real network is added here: the connection to sshd opens one round trip plus one
one-way delay after the client connected (when the server's ``accept`` would return on a
real link), and nothing reaches either side earlier than it would there (the client's
banner arrives at 1.5 round trips, sshd's at 2, as over a real link).

    python -m tests.lab.relay --listen IP:22 --to 127.0.0.1:2222 --delay-ms 75 --jitter-ms 5
    python -m tests.lab.relay --robots ROBOTS.json --delay-ms 75

``--robots``: one relay process for many robots (a lab of hundreds: one Python process per
robot would cost ~12 MB and ~0.25 s of CPU each). The file is a JSON list of
``{"netns": "/run/netns/NS", "listen": "IP:22", "to": "127.0.0.1:2222", "trace": FILE|null}``;
the relay creates each robot's listening socket and each connection to its sshd inside the
robot's network namespace (``setns`` on its own thread, then back: a socket stays in the
namespace it was created in), so the relay itself runs in the host's namespace.

Prints ``ready`` on stdout once it listens (on every address). Runs until killed. ``--trace FILE`` appends one
line per chunk: connection number, direction (``>`` client to sshd, ``<`` back), the time
the relay received it and the time it delivered it (seconds since the client connected),
and its size: the round trips of each connection, as a timeline.
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import ctypes
import json
import os
import random
import resource
import socket
import sys
from collections import deque
from collections.abc import Iterator
from dataclasses import dataclass

CLONE_NEWNET = 0x40000000


def _split(addr: str) -> tuple[str, int]:
    host, _, port = addr.rpartition(":")
    return host, int(port)


def _setns(fd: int) -> None:
    """setns(2) into a network namespace (os.setns from Python 3.12 on; libc before)."""
    if hasattr(os, "setns"):
        os.setns(fd, CLONE_NEWNET)
        return
    libc = ctypes.CDLL(None, use_errno=True)
    if libc.setns(fd, CLONE_NEWNET) != 0:
        err = ctypes.get_errno()
        raise OSError(err, f"setns: {os.strerror(err)}")


@contextlib.contextmanager
def netns(path: str | None) -> Iterator[None]:
    """This thread in the network namespace `path` (None: stay), then back in its own."""
    if path is None:
        yield
        return
    home = os.open("/proc/thread-self/ns/net", os.O_RDONLY)
    try:
        target = os.open(path, os.O_RDONLY)
        try:
            _setns(target)
        finally:
            os.close(target)
        try:
            yield
        finally:
            _setns(home)
    finally:
        os.close(home)


@dataclass(frozen=True)
class Route:
    """One robot: where the client connects, where its sshd listens, in which namespace."""

    listen: tuple[str, int]
    to: tuple[str, int]
    netns: str | None = None
    trace: str | None = None


def _socket(path: str | None) -> socket.socket:
    with netns(path):
        s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    s.setblocking(False)
    return s


async def _open_inner(route: Route) -> tuple[asyncio.StreamReader, asyncio.StreamWriter]:
    if route.netns is None:
        return await asyncio.open_connection(*route.to)
    s = _socket(route.netns)
    try:
        await asyncio.get_running_loop().sock_connect(s, route.to)
    except BaseException:
        s.close()
        raise
    return await asyncio.open_connection(sock=s)


def _listener(route: Route) -> socket.socket:
    s = _socket(route.netns)
    try:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        s.bind(route.listen)
        s.listen(256)
    except BaseException:
        s.close()
        raise
    return s


class Trace:
    """Where ``--trace`` lines go (nowhere without it)."""

    def __init__(self, path: str | None) -> None:
        self.out = open(path, "a", buffering=1) if path else None  # noqa: SIM115  # open while the relay runs
        self.count = 0

    def write(self, conn: int, arrow: str, start: float, got: float, sent: float, size: int) -> None:
        if self.out is not None:
            self.out.write(f"{conn} {arrow} {got - start:.4f} {sent - start:.4f} {size}\n")


class Link:
    """One direction of one connection: chunks delivered at their due time, in order."""

    def __init__(self, delay: float, jitter: float, rnd: random.Random) -> None:
        self.delay, self.jitter, self.rnd = delay, jitter, rnd
        self.last_due = 0.0
        self.trace: tuple[Trace, int, str, float] | None = None

    def due(self, now: float) -> float:
        d = self.delay + (self.rnd.uniform(-self.jitter, self.jitter) if self.jitter else 0.0)
        self.last_due = max(now + max(d, 0.0), self.last_due)  # never overtakes an earlier chunk
        return self.last_due


async def _pump(reader: asyncio.StreamReader, queue: asyncio.Queue[tuple[float, bytes]], link: Link) -> None:
    loop = asyncio.get_running_loop()
    try:
        while True:
            data = await reader.read(65536)
            now = loop.time()
            due = link.due(now)
            if link.trace is not None:
                trace, conn, arrow, start = link.trace
                trace.write(conn, arrow, start, now, due, len(data))
            queue.put_nowait((due, data))
            if not data:
                return
    except (ConnectionError, OSError):
        queue.put_nowait((link.due(loop.time()), b""))


async def _deliver(queue: asyncio.Queue[tuple[float, bytes]], writer: asyncio.StreamWriter | None,
                   opened: asyncio.Future[asyncio.StreamWriter | None] | None) -> None:
    loop = asyncio.get_running_loop()
    if writer is None:
        assert opened is not None
        writer = await opened
    try:
        while True:
            due, data = await queue.get()
            wait = due - loop.time()
            if wait > 0:
                await asyncio.sleep(wait)
            if writer is None:  # the inner connection failed: drain
                if not data:
                    return
                continue
            if not data:
                if writer.can_write_eof():
                    writer.write_eof()
                return
            writer.write(data)
            await writer.drain()
    except (ConnectionError, OSError):
        return


def _nodelay(writer: asyncio.StreamWriter) -> None:
    sock = writer.get_extra_info("socket")
    if sock is not None:
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)


async def _serve(routes: list[Route], delay: float, jitter: float, seed: int | None) -> None:
    rnd = random.Random(seed)
    loop = asyncio.get_running_loop()
    rtt = 2 * delay
    tasks: deque[asyncio.Task[None]] = deque(maxlen=4096 * len(routes))

    async def handle(route: Route, trace: Trace, creader: asyncio.StreamReader,
                     cwriter: asyncio.StreamWriter) -> None:
        _nodelay(cwriter)
        accepted = loop.time()
        up, down = Link(delay, jitter, rnd), Link(delay, jitter, rnd)
        trace.count += 1
        up.trace, down.trace = (trace, trace.count, ">", accepted), (trace, trace.count, "<", accepted)
        # what the client sends travels from the start; sshd's side opens when its accept would
        up_q: asyncio.Queue[tuple[float, bytes]] = asyncio.Queue()
        down_q: asyncio.Queue[tuple[float, bytes]] = asyncio.Queue()
        opened: asyncio.Future[asyncio.StreamWriter | None] = loop.create_future()
        up_task = asyncio.ensure_future(_pump(creader, up_q, up))
        deliver_up = asyncio.ensure_future(_deliver(up_q, None, opened))
        await asyncio.sleep(max(0.0, accepted + rtt + delay - loop.time()))
        try:
            sreader, swriter = await _open_inner(route)
        except OSError:
            opened.set_result(None)
            sock = cwriter.get_extra_info("socket")
            if sock is not None:  # refused inside: the client sees its connection reset
                sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, b"\x01\x00\x00\x00\x00\x00\x00\x00")
            cwriter.close()
            up_task.cancel()
            return
        _nodelay(swriter)
        opened.set_result(swriter)
        down.last_due = loop.time()
        down_task = asyncio.ensure_future(_pump(sreader, down_q, down))
        await asyncio.gather(deliver_up, _deliver(down_q, cwriter, None), return_exceptions=True)
        up_task.cancel()
        down_task.cancel()
        for w in (swriter, cwriter):
            w.close()

    def spawner(route: Route):  # type: ignore[no-untyped-def]
        trace = Trace(route.trace)

        def spawn(r: asyncio.StreamReader, w: asyncio.StreamWriter) -> None:
            tasks.append(asyncio.ensure_future(handle(route, trace, r, w)))

        return spawn

    servers = [await asyncio.start_server(spawner(route), sock=_listener(route)) for route in routes]
    sys.stdout.write("ready\n")
    sys.stdout.flush()
    await asyncio.gather(*(server.serve_forever() for server in servers))


def _routes(path: str) -> list[Route]:
    with open(path, encoding="utf-8") as f:
        items = json.load(f)
    return [Route(_split(x["listen"]), _split(x["to"]), x.get("netns"), x.get("trace")) for x in items]


def _raise_nofile() -> None:
    """Two descriptors per open connection and one per listener: the hard limit, not 1024."""
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    if soft != hard:
        resource.setrlimit(resource.RLIMIT_NOFILE, (hard, hard))


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m tests.lab.relay", description=__doc__.splitlines()[0])
    p.add_argument("--listen", help="IP:PORT the client connects to")
    p.add_argument("--to", help="IP:PORT of sshd inside the namespace")
    p.add_argument("--robots", help="JSON list of robots to relay for (instead of --listen/--to)")
    p.add_argument("--delay-ms", type=float, required=True, help="one-way delay (half the round trip)")
    p.add_argument("--jitter-ms", type=float, default=0.0, help="each chunk: delay ± up to this much")
    p.add_argument("--seed", type=int, default=None)
    p.add_argument("--trace", default=None, help="append a line per chunk to this file")
    a = p.parse_args(argv)
    if a.robots:
        if a.listen or a.to or a.trace:
            p.error("--robots replaces --listen, --to and --trace")
        routes = _routes(a.robots)
    elif a.listen and a.to:
        routes = [Route(_split(a.listen), _split(a.to), None, a.trace)]
    else:
        p.error("--listen and --to, or --robots")
    _raise_nofile()
    asyncio.run(_serve(routes, a.delay_ms / 1000.0, a.jitter_ms / 1000.0, a.seed))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
