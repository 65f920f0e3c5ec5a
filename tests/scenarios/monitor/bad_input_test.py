"""Bad monitor input through the rcsim executable: each case exits 2 with one message naming the
value, or the file and line (docs/monitor.md).

usage: bad_input_test.py RCSIM TESTS_DIR"""
import os
import shutil
import socket
import subprocess
import sys
import tempfile


def main(rcsim, here):
    board = os.path.join(here, "board.yaml")
    tmp = tempfile.mkdtemp(prefix="rcsim-monitor-bad-")

    def scenario(name, text):
        path = os.path.join(tmp, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    head = "duration_s: 0.01\nmain_cpu: {motion: true}\n"
    busy = socket.socket()
    busy.bind(("127.0.0.1", 0))
    busy.listen(1)
    cases = [
        ("a port that is not a number", [board, "--monitor", "127.0.0.1:http"], "the port must be a number 0..65535"),
        ("a port out of range", [board, "--monitor", "70000"], "'70000': the port must be a number"),
        ("a host name instead of an address", [board, "--monitor", "localhost:0"], "is not a numeric IPv4 or IPv6 address"),
        ("a port in use", [board, "--monitor", "127.0.0.1:%d" % busy.getsockname()[1]], "cannot listen"),
        ("a motion-only scenario", [scenario("m.yaml", "motion: {duration_s: 0.1}\n"), "--monitor", "0"],
         "has a 'motion:' section"),
        ("an unknown key in the section", [scenario("k.yaml", head + "monitor:\n  listne: '0'\n")], "k.yaml:4"),
        ("a bad listen address in the section", [scenario("l.yaml", head + "monitor:\n  listen: 'x:y'\n")],
         "l.yaml:4: 'monitor.listen' = 'x:y'"),
        ("a command token of three characters",
         [scenario("t.yaml", head + "monitor:\n  commands:\n    - {at_ms: 1, token: SVX}\n")], "t.yaml:5"),
        ("a negative command time",
         [scenario("n.yaml", head + "monitor:\n  commands:\n    - {at_ms: -1, token: SV}\n")], "n.yaml:5"),
    ]
    failures = 0
    for what, args, expect in cases:
        p = subprocess.run([rcsim, "run", *args], capture_output=True, text=True, timeout=20)
        ok = p.returncode == 2 and expect in p.stderr
        print(("ok    " if ok else "FAIL  ") + "%s: exit %d, %s" % (what, p.returncode, p.stderr.strip()[:200]))
        failures += not ok
    busy.close()
    shutil.rmtree(tmp, ignore_errors=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
