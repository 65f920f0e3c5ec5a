"""Starts `rcsim run SCENARIO --modbus 127.0.0.1:0 [extra...]` and finds the port it printed;
raw Modbus TCP helpers for the tests that send what a well-behaved client would not."""
import os
import re
import select
import socket
import struct
import subprocess
import tempfile
import time


class Rcsim:
    def __init__(self, rcsim, scenario, *extra, timeout=20.0):
        self.err = tempfile.TemporaryFile(mode="w+")  # a file: a pipe nobody reads could fill up
        self.out = tempfile.TemporaryDirectory(prefix="rcsim-modbus-")
        # Unbuffered: select() sees what Python has not read yet, lines are split here.
        self.proc = subprocess.Popen([rcsim, "run", scenario, "--out", self.out.name, "--modbus", "127.0.0.1:0", *extra],
                                     stdout=subprocess.PIPE, stderr=self.err, bufsize=0)
        self.lines = []
        self.port = self.http_port = None
        pending = b""
        end = time.monotonic() + timeout
        while time.monotonic() < end and (self.port is None or ("--monitor" in extra and self.http_port is None)):
            r, _, _ = select.select([self.proc.stdout], [], [], 0.2)
            if r:
                chunk = os.read(self.proc.stdout.fileno(), 4096)
                if not chunk:
                    break
                pending += chunk
            while b"\n" in pending:
                raw_line, pending = pending.split(b"\n", 1)
                line = raw_line.decode() + "\n"
                self.lines.append(line)
                m = re.match(r"modbus: 127\.0\.0\.1:(\d+) ", line)
                if m:
                    self.port = int(m.group(1))
                m = re.match(r"monitor: http://127\.0\.0\.1:(\d+)/", line)
                if m:
                    self.http_port = int(m.group(1))
            if self.proc.poll() is not None:
                break
        self.pending = pending  # the start of a line not yet complete
        if self.port is None:
            self.proc.kill()
            raise RuntimeError("rcsim printed no modbus port: " + "".join(self.lines) + self.stderr())

    def stderr(self):
        self.err.flush()
        self.err.seek(0)
        return self.err.read()

    def finish(self, timeout=30.0):
        out, _ = self.proc.communicate(timeout=timeout)
        return self.proc.returncode, "".join(self.lines) + (self.pending + out).decode(errors="replace"), self.stderr()

    def kill(self):
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.communicate()


def adu(tid, unit, pdu, protocol=0, length=None):
    """An MBAP header and PDU; `length` overrides the header's length field."""
    return struct.pack(">HHHB", tid, protocol, len(pdu) + 1 if length is None else length, unit) + pdu


def recv_adu(sock, timeout=3.0):
    """One response ADU, or b'' when the server closed the connection."""
    sock.settimeout(timeout)
    data = b""
    while len(data) < 6 or len(data) < 6 + struct.unpack(">H", data[4:6])[0]:
        chunk = sock.recv(300)
        if not chunk:
            return b""
        data += chunk
    return data


def raw(port, payload, timeout=3.0):
    """Sends `payload` on a new connection; the first response ADU (b'' if closed)."""
    s = socket.create_connection(("127.0.0.1", port), timeout=timeout)
    try:
        s.sendall(payload)
        return recv_adu(s, timeout)
    except (ConnectionResetError, socket.timeout):
        return b""
    finally:
        s.close()


def sim_time_ms(client):
    r = client.read_input_registers(0, 2, slave=1)
    return r.registers[0] << 16 | r.registers[1]
