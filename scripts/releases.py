#!/usr/bin/env python3
"""Write docs/releases.md: what each supported release reads from where (launch arguments, files
and their paths in the container, image, compose template), from panther-ops' own catalogue
(panther_ops/conformance/releases.py says which parts).

Examples:
  python scripts/releases.py             # (re)write docs/releases.md
  python scripts/releases.py --check     # exit 1 and say so when the page is stale

Exit status: 0 written or current, 1 with --check when the page differs, 2 on bad usage.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from panther_ops.conformance.releases import render  # noqa: E402

PAGE = ROOT / "docs" / "releases.md"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="scripts/releases.py", description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=PAGE, help="the page to write (default docs/releases.md)")
    parser.add_argument("--check", action="store_true", help="change nothing: exit 1 when the page is stale")
    args = parser.parse_args(argv)
    text = render()
    current = args.out.read_text(encoding="utf-8") if args.out.is_file() else None
    if args.check:
        if current != text:
            print(f"{args.out}: stale; run python scripts/releases.py", file=sys.stderr)
            return 1
        return 0
    if current != text:
        args.out.write_text(text, encoding="utf-8")
        print(f"{args.out}: written", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
