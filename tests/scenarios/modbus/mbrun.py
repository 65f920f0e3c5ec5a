"""Starts `rcsim run SCENARIO --modbus 127.0.0.1:0 [extra...]` and finds the port it printed;
raw Modbus TCP helpers for the tests that send what a well-behaved client would not."""
import os
import socket
import struct
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
import rcsim_test  # noqa: E402


class Rcsim(rcsim_test.Rcsim):
    """The run, its --out folder a temporary one; port (and http_port with --monitor) from the lines
    it prints, waited for up to `timeout` seconds."""

    def __init__(self, rcsim, scenario, *extra, timeout=20.0):
        self.out = tempfile.TemporaryDirectory(prefix="rcsim-modbus-")
        patterns = {"modbus": r"modbus: 127\.0\.0\.1:(\d+) "}
        if "--monitor" in extra:
            patterns["monitor"] = r"monitor: http://127\.0\.0\.1:(\d+)/"
        super().__init__(rcsim, ["run", scenario, "--out", self.out.name, "--modbus", "127.0.0.1:0", *extra],
                         patterns, timeout=timeout)
        self.port = int(self.found["modbus"].group(1))
        self.http_port = int(self.found["monitor"].group(1)) if "monitor" in self.found else None


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
