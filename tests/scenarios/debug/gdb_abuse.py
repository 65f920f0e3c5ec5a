#!/usr/bin/env python3
"""Abuse of the gdb endpoint of `rcsim run --gdb` (docs/tools.md "gdb", "Limits"; issue #33).

usage: gdb_abuse.py CASE RCSIM SCENARIO WORKDIR

The scenario is paced to real time (paced_run.yaml, 1.5 s), so "keeps its pace" means: the run
ends by itself within its duration plus the time gdb held it plus a margin. Memory is VmHWM from
/proc/PID/status, sampled while the run lives, against VmRSS once the debugger is attached.

CASE
  flood    while the board runs, a client floods `$g#67` (up to 100 MB in 1 s): it is dropped
           once it has sent more than the stub reads while running (64 KiB), with a line on
           stderr; memory stays bounded; a second client then connects, sends 30 KB of packets
           while the board runs (ignored, noted) and Ctrl-C, which is answered T02 within 1 s.
  deaf     while the board is held, a client sends `m` requests (4 KB replies) and reads
           nothing: the stub never blocks on it, drops it ("does not read its replies") and the
           run goes on to its end.
  sigterm  the same deaf client, then SIGTERM: rcsim ends within 1 s, exit 143, report.json
           written with interrupted: true.
  fuzz     a seeded mix while held (random bytes, truncated, oversized and bad-checksum packets,
           well-framed packets with bad arguments) after each of which the stub still answers
           '?'; random bytes while the board runs, then Ctrl-C (T02 within 1 s). The run ends by
           itself and its report.json is byte-identical to a run without gdb.
"""
import filecmp
import json
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import threading
import time

from gdb_garbage import GDB_LISTENING, connect, frame, read_for  # the RSP framing and socket helpers
from rcsim_test import Rcsim, rss_kib, status_kib  # tests/support, on the path since gdb_garbage's import

MARGIN_S = 4.0      # a paced run may end this much later than duration + held time
MEMORY_MB = 64      # VmHWM may exceed the attached VmRSS by this much
CTRL_C_S = 1.0      # Ctrl-C while running is answered within this
SIGTERM_S = 1.0     # SIGTERM ends the run within this


class Run(Rcsim):
    """rcsim run SCENARIO --gdb 127.0.0.1:0 --gdb-wait, its port, its stderr and its peak memory."""

    def __init__(self, rcsim, scenario, out):
        self.out = out
        super().__init__(rcsim, ["run", scenario, "--out", out, "--reproducible", "--gdb", "127.0.0.1:0", "--gdb-wait"],
                         {"gdb": GDB_LISTENING}, stderr=open(out + ".err", "w+"))
        self.port = int(self.found["gdb"].group(1))
        threading.Thread(target=self.proc.stdout.read, daemon=True).start()
        self.hwm_kb = 0
        threading.Thread(target=self._sample, daemon=True).start()

    def _sample(self):
        while self.proc.poll() is None:
            v = status_kib(self.proc.pid, "VmHWM")
            if v:
                self.hwm_kb = max(self.hwm_kb, v)
            time.sleep(0.02)

    def rss_kb(self):
        return rss_kib(self.proc.pid)

    def log(self):
        self.err.seek(0)
        return self.err.read()

    def wait_log(self, text, seconds):
        end = time.time() + seconds
        while time.time() < end and text not in self.log():
            time.sleep(0.05)
        return text in self.log()

    def wait(self, seconds, what):
        try:
            self.proc.wait(timeout=seconds)
        except subprocess.TimeoutExpired:
            self.kill()
            raise SystemExit("FAIL: %s: rcsim still running after %.1f s\n%s" % (what, seconds, self.log()))

    def kill(self):
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()


def attach(run):
    """Connects and asks '?': the board is held for the new debugger."""
    s = connect(run.port)
    s.sendall(frame(b"?"))
    got = read_for(s, 5, until=b"#")
    if b"$T05" not in got:
        run.kill()
        raise SystemExit("FAIL: no stop reply to '?': %r\n%s" % (got, run.log()))
    return s


def resume(s):
    """'c', and its acknowledgement: what is sent after it arrives while the board runs."""
    s.sendall(frame(b"c"))
    read_for(s, 5, until=b"+")


def ctrl_c(run, s):
    t = time.time()
    s.sendall(b"\x03")
    got = read_for(s, 5, until=b"$T02#")
    took = time.time() - t
    if b"$T02#" not in got or took > CTRL_C_S:
        run.kill()
        raise SystemExit("FAIL: Ctrl-C answered after %.2f s: %r\n%s" % (took, got[-200:], run.log()))


def send_without_reading(s, data, seconds):
    """Sends `data` over and over for `seconds` without reading; True when the stub dropped us."""
    s.setblocking(False)
    end = time.time() + seconds
    sent = 0
    while time.time() < end and sent < 100 << 20:
        try:
            sent += s.send(data)
        except BlockingIOError:
            time.sleep(0.005)
        except OSError:
            return True
    return False


def check_memory(run, base_kb):
    if os.environ.get("RCSIM_SANITIZED"):  # ASan's quarantine holds freed memory (CMakeLists.txt)
        print("memory bound not judged in a sanitizer build: VmHWM %d kB" % run.hwm_kb)
        return
    if run.hwm_kb > base_kb + MEMORY_MB * 1024:
        raise SystemExit("FAIL: VmHWM %d kB, attached at %d kB\n%s" % (run.hwm_kb, base_kb, run.log()))


def case_flood(run, duration):
    s = attach(run)
    base = run.rss_kb()
    resume(s)
    t0 = time.time()
    dropped = send_without_reading(s, b"$g#67" * 10000, 1.0)
    s.close()
    assert run.wait_log("while the board ran", 3), "FAIL: no line for the flood:\n" + run.log()
    assert dropped or "dropped" in run.log(), "FAIL: the flooding client was kept:\n" + run.log()
    s = attach(run)
    resume(s)
    s.sendall(b"$g#67" * 5000)
    ctrl_c(run, s)
    resume(s)
    s.close()
    run.wait(duration + MARGIN_S, "after a flood")
    assert run.proc.returncode == 0, "FAIL: rcsim exited %d\n%s" % (run.proc.returncode, run.log())
    assert time.time() - t0 < duration + MARGIN_S, "FAIL: the run lost its pace"
    assert "ignored 5000 packets sent while the board ran" in run.log(), "FAIL: no note:\n" + run.log()
    check_memory(run, base)
    assert os.path.exists(run.out + "/report.json"), "FAIL: no report.json"
    print("flood while running: dropped the client, memory bounded, Ctrl-C answered, run kept its pace")


def m_request():
    return frame(b"m0,1000")


def case_deaf(run, duration):
    s = attach(run)
    base = run.rss_kb()
    t0 = time.time()
    send_without_reading(s, m_request() * 64, 3.0)
    assert run.wait_log("does not read its replies", 3), "FAIL: the deaf client was kept:\n" + run.log()
    s.close()
    run.wait(duration + MARGIN_S + 3, "after a client that never reads")
    assert run.proc.returncode == 0, "FAIL: rcsim exited %d\n%s" % (run.proc.returncode, run.log())
    assert time.time() - t0 < duration + MARGIN_S + 3, "FAIL: the run lost its pace"
    check_memory(run, base)
    assert os.path.exists(run.out + "/report.json"), "FAIL: no report.json"
    print("a client that never reads: dropped, the run went on to its end")


def case_sigterm(run, duration):
    s = attach(run)
    # Held 1.5 s (less than the 2 s a reply may stay untaken): the hold must not delay the end.
    send_without_reading(s, m_request() * 64, 1.5)
    t = time.time()
    run.proc.send_signal(signal.SIGTERM)
    run.wait(5, "after SIGTERM")
    took = time.time() - t
    s.close()
    assert run.proc.returncode == 143, "FAIL: exit %d after SIGTERM\n%s" % (run.proc.returncode, run.log())
    assert took <= SIGTERM_S, "FAIL: SIGTERM took %.2f s" % took
    report = json.load(open(run.out + "/report.json"))
    assert report.get("interrupted") is True, "FAIL: report.json does not say interrupted"
    print("SIGTERM with a client that never reads: exit 143 in %.2f s, report.json written" % took)


def fuzz_items(rng):
    """What a confused or hostile client sends while the board is held; none of it changes it."""
    noise = bytes(rng.randrange(256) for _ in range(4096))
    yield noise
    yield b"".join(b"$m%x,%x" % (rng.randrange(1 << 20), rng.randrange(64)) for _ in range(50))  # truncated
    yield b"$" + b"A" * 20000 + b"#00"                    # oversized, bad checksum
    yield frame(b"m" + b"0" * 20000)                       # oversized, good checksum
    yield b"".join(frame(b"g")[:-2] + b"%02x" % ((sum(b"g") + 1 + i) & 0xFF) for i in range(50))
    yield frame(b"g")[:-2] + b"zz"                         # a checksum that is not hex
    bad = [b"m0,ffffffff", b"mzz", b"m123456789,1", b"M0,2:zz", b"M0,ffffffff:00", b"M0,1", b"G00",
           b"P99=00", b"Pz", b"P8=", b"p1000", b"Z9,0,1", b"Z2,0,ffffffff", b"Z0", b"z1,",
           b"qXfer:features:read:target.xml:ffffffff,ffffffff", b"qXfer:features:read:x:0,1",
           b"qRcmd,zz", b"qRcmd," + b"uart 9".hex().encode(), b"X0,1:a", b"czz", b"s1000000000",
           b"H", b"T", b"!", b"", b"}"]
    for p in bad:
        yield frame(p)
    yield frame(b"?") * 50                                 # pipelined before any answer
    yield bytes(rng.choice(b"$#}*+-\x03ab0") for _ in range(4096))


def case_fuzz(run, duration, rcsim, scenario, work):
    rng = random.Random(33)
    s = attach(run)
    base = run.rss_kb()
    for i, item in enumerate(fuzz_items(rng)):
        s.sendall(item)
        # '$' restarts a packet whatever state the decoder is in after two checksum bytes.
        s.sendall(b"$$$" + frame(b"?"))
        got = read_for(s, 5, until=b"$T05#")
        if b"$T05#" not in got:
            run.kill()
            raise SystemExit("FAIL: item %d left the stub deaf: %r\n%s" % (i, got[-200:], run.log()))
    resume(s)
    s.sendall(bytes(rng.choice([c for c in range(256) if c not in (3, 0x24)]) for _ in range(20000)))
    ctrl_c(run, s)
    resume(s)
    s.close()
    run.wait(duration + MARGIN_S + 5, "after the fuzz")
    assert run.proc.returncode == 0, "FAIL: rcsim exited %d\n%s" % (run.proc.returncode, run.log())
    check_memory(run, base)
    subprocess.run([rcsim, "run", scenario, "--out", work + "/ref", "--reproducible"], check=True,
                   stdout=subprocess.DEVNULL)
    assert filecmp.cmp(work + "/ref/report.json", run.out + "/report.json", shallow=False), \
        "FAIL: report.json differs from the run without gdb"
    print("fuzz: every item answered or refused, the stub kept answering; report unchanged")


def main():
    case, rcsim, scenario, work = sys.argv[1:5]
    duration = float(re.search(r"^duration_s: *([0-9.]+)", open(scenario).read(), re.M).group(1))
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    run = Run(rcsim, scenario, work + "/dbg")
    try:
        if case == "flood":
            case_flood(run, duration)
        elif case == "deaf":
            case_deaf(run, duration)
        elif case == "sigterm":
            case_sigterm(run, duration)
        elif case == "fuzz":
            case_fuzz(run, duration, rcsim, scenario, work)
        else:
            raise SystemExit("usage: gdb_abuse.py flood|deaf|sigterm|fuzz RCSIM SCENARIO WORKDIR")
    finally:
        run.kill()


if __name__ == "__main__":
    main()
