"""The ``pasibot`` command line (also ``python -m pasibot_pin``).

Each subcommand lives in its own module of :mod:`pasibot_pin.cli` and registers
itself with ``register(subparsers)``. Everything runs headless and writes files.

Errors: bad input (``ValueError``, ``FileExistsError``) and a file the system refuses
(``OSError``) are one line ``pasibot CMD: error: ...`` with exit code 2, never a traceback; so are
argparse's own errors (no usage block). Every numeric flag is checked against its range
(:mod:`pasibot_pin.cli.bounds`) before the command runs; ``-2e-1`` is a number, not an option.
SIGTERM and Ctrl-C stop the command, its child processes (process-pool workers, the meshcat
server) and their children; files being written are left under no name (exit code 143 / 130).
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import os
import re
import signal
import sys
import time

# Every matrix here is small (a few hundred rows at most): OpenBLAS worker threads only spin, on
# CPU the pool's other worker needs (a batched solve cost 10x the CPU with them, measured). One
# BLAS thread per process unless the caller chose otherwise. It must be set before numpy is first
# imported, which the package's __init__ (run before this module) does: pasibot_pin/__init__.py
# sets it for our commands; this line only covers running this file some other way.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import pinocchio as pin  # noqa: E402

from pasibot_pin import __version__, _interrupted_at_start  # noqa: E402
from pasibot_pin.cli import COMMANDS  # noqa: E402
from pasibot_pin.cli.bounds import BOUNDS, check_flags  # noqa: E402
from pasibot_pin.files import remove_temporaries  # noqa: E402

NEGATIVE_NUMBER = re.compile(r"^-(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?$|^-(?:inf|infinity|nan)$", re.IGNORECASE)
"""What argparse reads as a negative number, not an option: ``-2``, ``-.5``, ``-2e-1``, ``-5E-2``, ``-inf``
(argparse's own pattern misses exponents, so ``--com-dx -5e-2`` was read as an unknown option)."""


class OneLineParser(argparse.ArgumentParser):
    """An argument parser whose errors are one line, ``pasibot CMD: error: ...`` (exit code 2), like the commands'."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = NEGATIVE_NUMBER

    def error(self, message: str):
        """Print ``PROG: error: MESSAGE`` on one line and exit with code 2 (no usage block).

        A value argparse cannot read (``--samples 1e9``, ``--mu abc``) gets the flag's valid range too.
        """
        text = re.sub(r"'([^']{40})[^']+'", r"'\1...'", " ".join(message.split()))  # a 5,000-digit value, cut
        named = re.match(r"argument (--[\w-]+)(?:/[\w-]+)?: ", text)
        bound = BOUNDS.get(self.prog.split()[-1], {}).get(named.group(1)) if named else None
        if named and bound is not None:
            text += f"; {named.group(1)} must be {bound.text()}"
        self.exit(2, f"{self.prog}: error: {text}\n")


class Terminated(BaseException):
    """Raised in the main process by SIGTERM (a ``BaseException``, like Ctrl-C's: ``finally`` blocks run)."""


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every subcommand registered."""
    parser = OneLineParser(prog="pasibot", description="PASIBOT closed-loop biped in Pinocchio")
    parser.add_argument("--version", action="version", version=f"pasibot {__version__} (pin {pin.__version__})")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND", parser_class=OneLineParser)
    for name in COMMANDS:
        importlib.import_module(f"pasibot_pin.cli.{name}").register(sub)
    for command in sub.choices.values():  # --help is plain text: no docstring markup
        command.description = plain_text(command.description)
        for action in command._actions:
            action.help = plain_text(action.help)
    return parser


_ROLE = re.compile(r":(?:func|mod|class|data|meth|attr|obj):`~?([^`]+)`")


def plain_text(text: str | None) -> str | None:
    """Docstring markup made plain: ``code`` -> code, :func:`~pkg.mod.name` -> name."""
    if text is None:
        return None
    text = _ROLE.sub(lambda m: m.group(1).split(".")[-1], text)
    return text.replace("``", "")


def descendants(pid: int | None = None) -> list[int]:
    """Pids of every living descendant of ``pid`` (default this process), children first (Linux /proc)."""
    pid = os.getpid() if pid is None else pid
    children: dict[int, list[int]] = {}
    try:
        entries = os.listdir("/proc")
    except OSError:
        return []
    for entry in entries:
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat") as handle:
                stat = handle.read()
        except OSError:
            continue
        fields = stat[stat.rfind(")") + 2 :].split()
        if fields and fields[0] != "Z":
            children.setdefault(int(fields[1]), []).append(int(entry))
    out: list[int] = []
    todo = list(children.get(pid, []))
    while todo:
        child = todo.pop(0)
        out.append(child)
        todo.extend(children.get(child, []))
    return out


def stop_descendants(timeout: float = 3.0) -> None:
    """SIGTERM every descendant process, then SIGKILL those still alive after ``timeout`` [s]."""
    pids = descendants()
    for pid in pids:
        try:
            os.kill(pid, signal.SIGTERM)
        except OSError:
            pass
    deadline = time.monotonic() + timeout
    while pids and time.monotonic() < deadline:
        for pid in list(pids):
            try:  # reap our own children; others (grandchildren) are reaped by their parent or init
                os.waitpid(pid, os.WNOHANG)
            except ChildProcessError:
                pass
            if not os.path.exists(f"/proc/{pid}") or _is_zombie(pid):
                pids.remove(pid)
        time.sleep(0.02)
    for pid in pids:
        try:
            os.kill(pid, signal.SIGKILL)
        except OSError:
            pass


def _is_zombie(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as handle:
            stat = handle.read()
    except OSError:
        return True
    return stat[stat.rfind(")") + 2 :].startswith("Z")


def _install_signal_handlers() -> None:
    """SIGTERM/SIGINT: in this process, stop the children and raise; in a forked child, die at once."""
    main_pid = os.getpid()

    def handler(signum, frame):
        remove_temporaries()  # the files this process is writing, never left under a .part name
        if os.getpid() != main_pid:  # a forked worker inherited this handler: die as by default
            signal.signal(signum, signal.SIG_DFL)
            os.kill(os.getpid(), signum)
            return
        signal.signal(signal.SIGTERM, signal.SIG_DFL)  # a second signal stops at once
        signal.signal(signal.SIGINT, signal.SIG_DFL)
        stop_descendants()
        raise Terminated() if signum == signal.SIGTERM else KeyboardInterrupt()

    signal.signal(signal.SIGTERM, handler)
    signal.signal(signal.SIGINT, handler)


def _quiet_stdout() -> None:
    """Point stdout at /dev/null, so that the interpreter's last flush meets no closed pipe."""
    with contextlib.suppress(OSError, ValueError):
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)


def _os_message(err: OSError) -> str:
    if err.filename is not None and err.strerror:
        return f"{err.filename}: {err.strerror}"
    return str(err) or type(err).__name__


def main(argv: list[str] | None = None) -> int:
    """Run the CLI; returns the exit code (2 for bad input, with a one-line message)."""
    parser = build_parser()
    args = parser.parse_args(argv)
    is_entry_point = argv is None
    if is_entry_point:
        _install_signal_handlers()
    elif signal.getsignal(signal.SIGINT) is _interrupted_at_start:  # called as a function: Ctrl-C raises again
        signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        check_flags(args.command, args)  # every numeric flag within its range, before any work
        return int(args.func(args) or 0)
    except BrokenPipeError:  # the reader left (`pasibot walk | head -1`): what it read is all it wanted
        _quiet_stdout()
        return 0
    except (ValueError, FileExistsError) as err:
        print(f"pasibot {args.command}: error: {err}", file=sys.stderr)
        return 2
    except OSError as err:
        print(f"pasibot {args.command}: error: {_os_message(err)}", file=sys.stderr)
        return 2
    except MemoryError:
        print(f"pasibot {args.command}: error: out of memory; ask for fewer samples or steps", file=sys.stderr)
        return 2
    except (KeyboardInterrupt, Terminated) as err:
        if not is_entry_point:
            raise
        stop_descendants()
        terminated = isinstance(err, Terminated)
        print(f"pasibot {args.command}: {'terminated' if terminated else 'interrupted'}", file=sys.stderr)
        return 128 + (signal.SIGTERM if terminated else signal.SIGINT)


if __name__ == "__main__":
    sys.exit(main())
