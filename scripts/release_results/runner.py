"""Running fnopt for a part: each command's whole output in the part's log, its progress echoed under the
part's name, a failure raised as PartFailed naming the command; and the command as results.md shows it."""

import os
import re
import shlex
import subprocess
import threading

# fnopt's progress bar in a log (util/progress_bar.hpp): "LABEL 3/10  30% elapsed 1m05s ETA 2m31s ...".
PROGRESS_LINE = re.compile(r" \d+/\d+ +\d+% elapsed \S+ ETA ")


class PartFailed(Exception):
    """A part's command failed or its output is missing; the message names the part."""


def command_text(cmd):
    """The command as docs show it: 'fnopt ...' with the output directory relative to --out (and without
    --resume, which changes what is run, not what is measured)."""
    return " ".join(shlex.quote(c) for c in ["fnopt"] + [c for c in cmd[1:] if c != "--resume"])


def binary_version(binary):
    """What `fnopt --version` prints (its standard output and error, stripped); "" when it prints nothing."""
    r = subprocess.run([binary, "--version"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       universal_newlines=True)
    return r.stdout.strip()


class Runner:
    """Runs fnopt commands for one part, their output in the part's log files."""

    def __init__(self, binary, out):
        self.binary = binary
        self.out = out
        self._running = set()  # the fnopt processes running now (several with --jobs), for kill_all()
        self._lock = threading.Lock()
        self._killed = False

    def run(self, part, args):
        """Runs fnopt with args in --out (the paths in args are relative to it); its output is logged in
        OUT/logs/PART.txt. Returns its standard output; raises PartFailed when it fails."""
        cmd = [self.binary] + args
        log = os.path.join(self.out, "logs", re.sub(r"[^A-Za-z0-9_.-]+", "_", part) + ".txt")
        os.makedirs(os.path.dirname(log), exist_ok=True)
        with open(log, "a", encoding="utf-8") as f:
            f.write("$ " + command_text(cmd) + "\n")
            f.flush()
            stdout, returncode = self._run_logged(part, cmd, f)
            f.write(stdout)
        if returncode != 0:
            with open(log, encoding="utf-8", errors="replace") as f:
                lines = [l.strip() for l in f.read().replace("\r", "\n").splitlines()
                         if l.strip() and not l.startswith("$ ")]
            raise PartFailed("'%s' exited with %d (%s; log %s)" %
                             (command_text(cmd), returncode, lines[-1] if lines else "no output", log))
        return stdout

    def _run_logged(self, part, cmd, log):
        """Runs cmd with its standard error into the log, echoing fnopt's progress lines (a line per 10 %, with
        the ETA) under the part's name, so that an hours-long part shows how far it is. Returns (stdout, exit
        status); an exception (SIGTERM included) kills the child first, as subprocess.run does."""
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True,
                                cwd=self.out)
        with self._lock:
            self._running.add(proc)
            if self._killed:
                proc.kill()  # started by a pool thread just as kill_all ran
        stdout = []
        reader = threading.Thread(target=lambda: stdout.append(proc.stdout.read()))
        reader.start()
        try:
            for line in proc.stderr:
                log.write(line)
                log.flush()
                if PROGRESS_LINE.search(line):
                    print("    %s: %s" % (part, line.strip()), flush=True)
            proc.wait()
        except BaseException:
            proc.kill()
            proc.wait()
            raise
        finally:
            reader.join()
            with self._lock:
                self._running.discard(proc)
        return "".join(stdout), proc.returncode

    def kill_all(self):
        """Kills every fnopt process running now, and any started after (the other runs of a failed or terminated
        run_all: the run stops)."""
        with self._lock:
            self._killed = True
            for proc in self._running:
                proc.kill()

    def rel(self, path):
        """path relative to --out, where fnopt runs: how the commands in results.md name it."""
        return os.path.relpath(path, self.out)
