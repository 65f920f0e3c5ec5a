"""What the Python tests share: the rcsim executable started with what it announces read back, the
ok/FAIL line of each check, a process's memory, and a frame of the host protocol.

A test imports it from its own location (the standard library only, so any python3 runs it):

    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
    from rcsim_test import check, failures  # noqa: E402
"""
import os
import re
import select
import subprocess
import tempfile
import time

# The bound of a wait for something that comes on any host, however loaded: only a hang outlasts
# it. The tests wait for the event itself, never a fixed time in its place.
HANG_S = 60.0

# ---- checks ------------------------------------------------------------------------------------

failures = []  # what failed, in order; a test exits 1 when it is not empty


def check(cond, what):
    """Prints the check as "ok" or "FAIL" and goes on, so one run shows every failure."""
    print(("ok    " if cond else "FAIL  ") + what)
    if not cond:
        failures.append(what)


# ---- a process's memory ------------------------------------------------------------------------

def status_kib(pid, key):
    """A figure of /proc/PID/status in KiB (VmRSS, VmHWM, ...); None once the process is gone."""
    try:
        with open("/proc/%d/status" % pid) as f:
            for line in f:
                if line.startswith(key + ":"):
                    return int(line.split()[1])
    except OSError:
        pass
    return None


def rss_kib(pid):
    """The resident size in KiB; 0 once the process is gone."""
    return status_kib(pid, "VmRSS") or 0


# ---- waiting -----------------------------------------------------------------------------------

def wait_for(pred, proc=None, timeout=20.0, poll=0.02):
    """Polls `pred` until it holds (True), `timeout` seconds pass or `proc` ends first (False).
    For what a run writes rather than prints: a port file, a pty's link."""
    end = time.monotonic() + timeout
    while not pred():
        if time.monotonic() > end or (proc is not None and proc.poll() is not None):
            return pred()
        time.sleep(poll)
    return True


class Rcsim:
    """`RCSIM ARGS...` started with its stdout read here until a line has matched each of
    `patterns` ({name: regex}; the matches in `found`), bounded by `timeout` seconds: the lines
    that say where the run listens ("monitor: http://127.0.0.1:PORT/", "modbus: 127.0.0.1:PORT ",
    "gdb: listening on 127.0.0.1:PORT"). `timeout` bounds a hang, not a start-up: a loaded host
    may take long to start rcsim. Missing a line then is an error (RuntimeError), unless
    `required` is false. stderr goes to `stderr` (a file; a temporary one by default: a pipe
    nobody reads could fill up and stop the run)."""

    def __init__(self, rcsim, args, patterns, timeout=HANG_S, stderr=None, env=None, required=True):
        self.err = stderr if stderr is not None else tempfile.TemporaryFile(mode="w+")
        # Unbuffered: select() sees what Python has not read yet, lines are split here.
        self.proc = subprocess.Popen([rcsim, *args], stdout=subprocess.PIPE, stderr=self.err, bufsize=0, env=env)
        self.lines = []     # the stdout lines read so far
        self.pending = b""  # the start of a line not yet complete
        self.found = {}
        end = time.monotonic() + timeout
        while len(self.found) < len(patterns) and time.monotonic() < end:
            ready, _, _ = select.select([self.proc.stdout], [], [], 0.2)
            if not ready:
                if self.proc.poll() is not None:
                    break
                continue
            chunk = os.read(self.proc.stdout.fileno(), 4096)
            if not chunk:
                break
            self.pending += chunk
            while b"\n" in self.pending:
                raw, self.pending = self.pending.split(b"\n", 1)
                line = raw.decode(errors="replace") + "\n"
                self.lines.append(line)
                for name, pattern in patterns.items():
                    m = name not in self.found and re.match(pattern, line)
                    if m:
                        self.found[name] = m
        missing = [name for name in patterns if name not in self.found]
        if missing and required:
            self.kill()
            raise RuntimeError("rcsim printed no %s line within %g s: %s%s"
                               % (", ".join(missing), timeout, "".join(self.lines), self.stderr()))

    def stderr(self):
        """What the run wrote on stderr so far."""
        self.err.flush()
        self.err.seek(0)
        return self.err.read()

    def finish(self, timeout=30.0):
        """Waits for the run to end; (exit code, all of stdout, stderr)."""
        out, _ = self.proc.communicate(timeout=timeout)
        return self.proc.returncode, "".join(self.lines) + (self.pending + out).decode(errors="replace"), self.stderr()

    def kill(self):
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.communicate()


# ---- the host protocol -------------------------------------------------------------------------

SOH, STX, ETX, EOT, ENQ, ACK, NAK = b"\x01", b"\x02", b"\x03", b"\x04", b"\x05", b"\x06", b"\x15"


def protocol_frame(token, data, bch=b"00"):
    """docs/system.md §5.3: SOH T1 T2 STX B1 B2 data C1 C2 ETX, checksum = 8-bit sum of T1..data."""
    body = token + STX + bch + data
    return SOH + body + b"%02X" % (sum(body) & 0xFF) + ETX
