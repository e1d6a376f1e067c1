"""The ``freefloat`` command installed by ``pip install ./python``: the same command line as
the Rust binary (``cargo install --path .``), the library's own code run in this process, with
the same output and exit codes (0 success, 2 bad input, 3 no certified plan)."""

from __future__ import annotations

import sys

from ._freefloat import _cli_main


def main() -> None:
    """Runs ``freefloat`` with this process' arguments and exits with its code."""
    sys.exit(_cli_main(["freefloat", *sys.argv[1:]]))


if __name__ == "__main__":
    main()
