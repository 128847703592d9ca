"""A network serial server for tests and benchmarks: a pseudo-terminal pair, a command (the
IUT) started on its slave side, and the master side served on 127.0.0.1 as RFC 2217 (built
on pyserial's ``serial.rfc2217.PortManager``) or as a raw TCP stream (``socket://``).

    python tests/fakes/port_server.py rfc2217|raw [--parmrk] COMMAND-WITH-{port}

Prints ``PORT <tcp port>`` on stdout once it listens, then serves one client at a time
until the command ends or the server gets SIGTERM (the command's process group is then
stopped). Events go to stderr, one line each (``BREAK on``, ``BREAK off``, ``client ...``).

A pseudo-terminal has no line conditions. With ``--parmrk`` the server stands for a tty
whose reader set PARMRK: it delivers a BREAK the client asks for (RFC 2217 SET-CONTROL
BREAK-ON) as ``FF 00 00`` and a data byte FF as ``FF FF``, in order with the data around it.
"""

from __future__ import annotations

import os
import select
import signal
import socket
import subprocess
import sys
import tty

from serial import rfc2217


class PtyPort:
    """What ``PortManager`` needs of a serial port, on the master side of a pty."""

    def __init__(self, fd: int, parmrk: bool):
        self.fd, self.parmrk = fd, parmrk
        self.baudrate, self.bytesize, self.parity, self.stopbits = 9600, 8, "N", 1
        self.xonxoff = self.rtscts = False
        self.dtr = self.rts = True
        self.cts = self.dsr = self.cd = True
        self.ri = False
        self._break = False
        self._out = bytearray()

    def put(self, data: bytes) -> None:
        """Data from the client, kept in order with the line conditions between it."""
        self._out += data.replace(b"\xff", b"\xff\xff") if self.parmrk else data

    def flush(self) -> None:
        view = memoryview(bytes(self._out))
        self._out.clear()
        while view:
            view = view[os.write(self.fd, view):]

    @property
    def break_condition(self) -> bool:
        return self._break

    @break_condition.setter
    def break_condition(self, on: bool) -> None:
        if on and not self._break:
            self.flush()
            if self.parmrk:
                os.write(self.fd, b"\xff\x00\x00")
        if on != self._break:
            log(f"BREAK {'on' if on else 'off'}")
        self._break = on

    def reset_input_buffer(self) -> None:
        pass

    def reset_output_buffer(self) -> None:
        pass


class Client:
    """One TCP connection, RFC 2217 or raw."""

    def __init__(self, conn: socket.socket, port: PtyPort, mode: str):
        conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self.conn, self.port = conn, port
        self.manager = rfc2217.PortManager(port, self) if mode == "rfc2217" else None

    def write(self, data: bytes) -> None:  # PortManager's connection
        self.conn.sendall(data)

    def to_client(self, data: bytes) -> None:
        self.conn.sendall(b"".join(self.manager.escape(data)) if self.manager else data)

    def from_client(self, data: bytes) -> None:
        if self.manager is None:
            self.port.put(data)
        else:
            for byte in self.manager.filter(data):   # commands act here, between the data
                self.port.put(byte)
        self.port.flush()


def log(line: str) -> None:
    sys.stderr.write(line + "\n")
    sys.stderr.flush()


def main() -> int:
    args = sys.argv[1:]
    if len(args) < 2 or args[0] not in ("rfc2217", "raw"):
        log("usage: port_server.py rfc2217|raw [--parmrk] COMMAND-WITH-{port}")
        return 2
    mode, args = args[0], args[1:]
    parmrk = args[0] == "--parmrk"
    command = " ".join(args[1:] if parmrk else args)
    master, slave = os.openpty()
    tty.setraw(slave)   # no echo, no line editing until the IUT sets its own mode
    port = PtyPort(master, parmrk)
    srv = socket.socket()
    srv.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    srv.bind(("127.0.0.1", 0))
    srv.listen(1)
    iut = subprocess.Popen("exec " + command.replace("{port}", os.ttyname(slave)), shell=True,
                           start_new_session=True)
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(0))
    print(f"PORT {srv.getsockname()[1]}", flush=True)
    client: Client | None = None
    try:
        while iut.poll() is None:
            fds = [srv, master] + ([client.conn] if client else [])
            r, _, _ = select.select(fds, [], [], 0.5)
            if srv in r:
                conn, addr = srv.accept()
                if client is not None:
                    client.conn.close()
                client = Client(conn, port, mode)
                log(f"client {addr[0]}:{addr[1]}")
            if master in r:
                data = os.read(master, 4096)
                if client is not None:   # nobody connected: the data is lost, as on a line
                    try:
                        client.to_client(data)
                    except OSError:
                        client = None
            if client is not None and client.conn in r:
                try:
                    data = client.conn.recv(4096)
                except OSError:
                    data = b""
                if not data:
                    log("client gone")
                    client.conn.close()
                    client = None
                else:
                    client.from_client(data)
    finally:
        stop(iut)
    return 0


def stop(proc: subprocess.Popen) -> None:
    """SIGTERM to the command's process group (so that it can write what it keeps), then
    SIGKILL to whatever is left of it."""
    for sig, grace in ((signal.SIGTERM, 2.0), (signal.SIGKILL, 5.0)):
        try:
            os.killpg(proc.pid, sig)
        except ProcessLookupError:
            break
        try:
            proc.wait(grace)
            break
        except subprocess.TimeoutExpired:
            pass


if __name__ == "__main__":
    sys.exit(main())
