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

Prints ``ready`` on stdout once it listens. Runs until killed. ``--trace FILE`` appends one
line per chunk: connection number, direction (``>`` client to sshd, ``<`` back), the time
the relay received it and the time it delivered it (seconds since the client connected),
and its size: the round trips of each connection, as a timeline.
"""

from __future__ import annotations

import argparse
import asyncio
import random
import socket
import sys
from collections import deque


def _split(addr: str) -> tuple[str, int]:
    host, _, port = addr.rpartition(":")
    return host, int(port)


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


async def _serve(listen: tuple[str, int], to: tuple[str, int], delay: float, jitter: float, seed: int | None,
                 trace: Trace) -> None:
    rnd = random.Random(seed)
    loop = asyncio.get_running_loop()
    rtt = 2 * delay
    tasks: deque[asyncio.Task[None]] = deque(maxlen=4096)

    async def handle(creader: asyncio.StreamReader, cwriter: asyncio.StreamWriter) -> None:
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
            sreader, swriter = await asyncio.open_connection(*to)
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

    def spawn(r: asyncio.StreamReader, w: asyncio.StreamWriter) -> None:
        tasks.append(asyncio.ensure_future(handle(r, w)))

    server = await asyncio.start_server(spawn, *listen, reuse_address=True, backlog=256)
    sys.stdout.write("ready\n")
    sys.stdout.flush()
    async with server:
        await server.serve_forever()


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m tests.lab.relay", description=__doc__.splitlines()[0])
    p.add_argument("--listen", required=True, help="IP:PORT the client connects to")
    p.add_argument("--to", required=True, help="IP:PORT of sshd inside the namespace")
    p.add_argument("--delay-ms", type=float, required=True, help="one-way delay (half the round trip)")
    p.add_argument("--jitter-ms", type=float, default=0.0, help="each chunk: delay ± up to this much")
    p.add_argument("--seed", type=int, default=None)
    p.add_argument("--trace", default=None, help="append a line per chunk to this file")
    a = p.parse_args(argv)
    asyncio.run(_serve(_split(a.listen), _split(a.to), a.delay_ms / 1000.0, a.jitter_ms / 1000.0, a.seed,
                       Trace(a.trace)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
