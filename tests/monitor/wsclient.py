"""A minimal WebSocket client (RFC 6455) and helpers to start rcsim with its monitor, on the Python
standard library alone: the monitor tests drive the JSON API (docs/monitor.md) and Chromium's
DevTools protocol with it."""
import base64
import json
import os
import re
import socket
import struct
import subprocess
import tempfile
import threading
import time

# The bound of a wait for something that comes on any host, however loaded: only a hang outlasts
# it. The tests wait for the event itself, never a fixed time in its place.
HANG_S = 60.0


def ws_frame(payload, opcode=1, length=None, mask=b"\x01\x02\x03\x04"):
    """One masked client frame (RFC 6455 5.2); `length` claims another payload length than the
    payload's (for the fuzz tests)."""
    n = len(payload) if length is None else length
    if n < 126:
        head = struct.pack("!BB", 0x80 | opcode, 0x80 | n)
    elif n < 65536:
        head = struct.pack("!BBH", 0x80 | opcode, 0x80 | 126, n)
    else:
        head = struct.pack("!BBQ", 0x80 | opcode, 0x80 | 127, n)
    return head + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(payload))


class WebSocket:
    """One client connection; text messages only (what the monitor and DevTools speak)."""

    def __init__(self, host, port, path, timeout=HANG_S):
        self.sock = socket.create_connection((host, port), timeout=timeout)
        key = base64.b64encode(os.urandom(16)).decode()
        self.sock.sendall((f"GET {path} HTTP/1.1\r\nHost: {host}:{port}\r\nUpgrade: websocket\r\n"
                           f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\n"
                           "Sec-WebSocket-Version: 13\r\n\r\n").encode())
        head = b""
        while b"\r\n\r\n" not in head:
            chunk = self.sock.recv(1)
            if not chunk:
                raise ConnectionError("closed during the handshake")
            head += chunk
        if b" 101 " not in head.split(b"\r\n", 1)[0]:
            raise ConnectionError("handshake refused: " + head.decode(errors="replace"))
        self.buf = b""

    def send_raw(self, payload, opcode=1):
        """One masked frame (clients must mask, RFC 6455 5.3)."""
        self.sock.sendall(ws_frame(payload, opcode, mask=os.urandom(4)))

    def send(self, obj):
        self.send_raw(json.dumps(obj).encode())

    def _read(self, n):
        while len(self.buf) < n:
            chunk = self.sock.recv(65536)
            if not chunk:
                raise ConnectionError("connection closed")
            self.buf += chunk
        out, self.buf = self.buf[:n], self.buf[n:]
        return out

    def recv(self):
        """The next text message (its fragments joined), parsed; ConnectionError when the server closed."""
        message = b""
        while True:
            b0, b1 = self._read(2)
            n = b1 & 0x7F
            if n == 126:
                n = struct.unpack("!H", self._read(2))[0]
            elif n == 127:
                n = struct.unpack("!Q", self._read(8))[0]
            payload = self._read(n)
            opcode = b0 & 0x0F
            if opcode == 8:
                raise ConnectionError("server closed the connection")
            if opcode == 9:  # ping: answer, keep reading
                self.send_raw(payload, opcode=10)
                continue
            if opcode in (1, 0):
                message += payload
                if b0 & 0x80:  # FIN: the last fragment
                    return json.loads(message)

    def recv_until(self, pred, timeout=HANG_S):
        """Messages until one satisfies pred (returned); the others are dropped."""
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            self.sock.settimeout(max(0.05, end - time.monotonic()))
            m = self.recv()
            if pred(m):
                return m
        raise TimeoutError("no matching message within %.1f s" % timeout)

    def request(self, obj, timeout=HANG_S):
        """Sends a request with a fresh id; returns its reply (ok or error)."""
        WebSocket._next_id = getattr(WebSocket, "_next_id", 0) + 1
        obj = dict(obj, id=WebSocket._next_id)
        self.send(obj)
        return self.recv_until(lambda m: m.get("id") == obj["id"], timeout)

    def close(self):
        try:
            self.sock.close()
        except OSError:
            pass


def http_get(host, port, path, timeout=HANG_S):
    """(status, body) of a GET."""
    s = socket.create_connection((host, port), timeout=timeout)
    s.sendall(f"GET {path} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n".encode())
    data = b""
    length = None  # Content-Length once the head is in: some servers keep the connection open
    while length is None or len(data) < length:
        chunk = s.recv(65536)
        if not chunk:
            break
        data += chunk
        if length is None and b"\r\n\r\n" in data:
            head = data.split(b"\r\n\r\n", 1)[0]
            m = re.search(rb"(?im)^content-length:\s*(\d+)", head)
            if m:
                length = len(head) + 4 + int(m.group(1))
    s.close()
    head, _, body = data.partition(b"\r\n\r\n")
    return int(head.split()[1]), body


class Rcsim:
    """rcsim run SCENARIO --monitor 127.0.0.1:0; url/port from the line it prints."""

    def __init__(self, rcsim, scenario, *extra, hang_s=HANG_S):
        self.err = tempfile.TemporaryFile(mode="w+")  # a file: a pipe nobody reads could fill up
        self.proc = subprocess.Popen([rcsim, "run", scenario, "--monitor", "127.0.0.1:0", *extra],
                                     stdout=subprocess.PIPE, stderr=self.err, text=True)
        self.stdout_lines = []
        # Lines until the monitor's, or the end of rcsim's output: a loaded host may take long to
        # start it, so there is no start-up deadline; the guard only ends a run that hangs before
        # the line (killed, its output ends). Blocking reads: select() on the pipe would not see a
        # line already in the reader's buffer.
        guard = threading.Timer(hang_s, self.proc.kill)
        guard.start()
        try:
            for line in self.proc.stdout:
                self.stdout_lines.append(line)
                m = re.match(r"monitor: (http://127\.0\.0\.1:(\d+)/)", line)
                if m:
                    self.url, self.port = m.group(1), int(m.group(2))
                    return
        finally:
            guard.cancel()
        self.proc.kill()
        self.proc.wait()
        raise RuntimeError("rcsim printed no monitor URL: " + "".join(self.stdout_lines) + self.stderr())

    def ws(self):
        return WebSocket("127.0.0.1", self.port, "/api/v1/ws")

    def stderr(self):
        """What rcsim wrote on stderr so far (the monitor's log lines)."""
        self.err.flush()
        self.err.seek(0)
        return self.err.read()

    def finish(self, timeout=30.0):
        """Waits for the run to end; (exit code, stdout, stderr)."""
        out, _ = self.proc.communicate(timeout=timeout)
        return self.proc.returncode, "".join(self.stdout_lines) + out, self.stderr()

    def kill(self):
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.communicate()
