"""The ``rubberfriction`` command.

Each feature owns a small command module exposing ``register(subparsers)``; this file only
collects them, so features can be added without touching each other.
"""

from __future__ import annotations

import argparse
import importlib
import logging
import sys
from typing import NoReturn

import rubberfriction
from rubberfriction.validation import InputError

# the command modules, in the order shown by --help
COMMAND_MODULES: tuple[str, ...] = (
    "rubberfriction.driver.cli.run",
    "rubberfriction.driver.cli.rerun",
    "rubberfriction.driver.cli.verify",
    "rubberfriction.driver.cli.surface",
    "rubberfriction.driver.cli.material",
    "rubberfriction.driver.cli.theory",
    "rubberfriction.driver.cli.adhesion",
    "rubberfriction.driver.cli.study",
    "rubberfriction.driver.cli.bench",
    "rubberfriction.driver.cli.scene",
)


class OneLineParser(argparse.ArgumentParser):
    """An argument parser whose errors are one line on stderr (``rubberfriction verify hertz:
    error: argument --R: invalid float value: 'abc' (see --help)``), exit status 2; its
    sub-command parsers are of the same class (argparse's default ``parser_class``)."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {' '.join(message.split())} (see {self.prog} "
                     "--help)\n")


def build_parser() -> argparse.ArgumentParser:
    units = "units: mm, s, t, N, MPa, mJ, K"
    parser = OneLineParser(
        prog="rubberfriction",
        description=f"Multiscale FEM rubber friction on rough road surfaces ({units}).",
    )
    parser.add_argument("--version", action="version",
                        version=f"rubberfriction {rubberfriction.__version__} ({units})")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMAND_MODULES:
        importlib.import_module(name).register(sub)
    return parser


def quiet_build_logging() -> None:
    """Warnings and errors only on the console.  FFCx compiles each new form with setuptools,
    which raises the root logger to INFO and printed every gcc command line (about 60 on a first
    run with a cold JIT cache); a root handler at WARNING keeps them out whatever the root level."""
    if not logging.root.handlers:
        logging.basicConfig(format="%(levelname)s: %(name)s: %(message)s")
    for handler in logging.root.handlers:
        if type(handler) is logging.StreamHandler:  # the console; not a test runner's capture
            handler.setLevel(logging.WARNING)


def main(argv: list[str] | None = None) -> int:
    quiet_build_logging()
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        return int(args.func(args) or 0)
    except InputError as err:  # bad input: one line, no traceback (real bugs still show theirs)
        return report_input_error(err)


def report_input_error(err: InputError) -> int:
    """Print ``rubberfriction: error: <message>`` as one line on stderr (rank 0 only under MPI)
    and return the command line's input-error status, 2."""
    mpi = sys.modules.get("mpi4py.MPI")  # only if a command imported it: never start MPI here
    if mpi is None or not mpi.Is_initialized() or mpi.COMM_WORLD.Get_rank() == 0:
        message = " ".join(str(err).split())  # one line, whatever the message holds
        print(f"rubberfriction: error: {message}", file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main())
