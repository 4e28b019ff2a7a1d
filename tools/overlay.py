#!/usr/bin/env python3
"""Add our modules, simulator core and example FINken aircraft to a Paparazzi tree, or take them off again.

Usage:
  tools/overlay.py install PAPARAZZI_HOME   add (refuses if any of our files exists there; names them)
  tools/overlay.py remove PAPARAZZI_HOME    take off what install added
  tools/overlay.py list                     the files install adds

No Paparazzi file is replaced; conf/abi.xml (and conf/messages.xml when the tree has one) gets our messages
between marker comments. Run `make static_h` in the tree after install or remove. Details:
tools/finken/paparazzi/overlay.py.
"""
import argparse
import sys

from finken.paparazzi.overlay import OverlayError, install, overlay_files, remove


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    for name in ("install", "remove"):
        sub.add_parser(name).add_argument("tree", help="the Paparazzi tree (PAPARAZZI_HOME)")
    sub.add_parser("list")
    args = parser.parse_args(argv)
    try:
        if args.command == "list":
            print("\n".join(overlay_files()))
        elif args.command == "install":
            manifest = install(args.tree)
            files = sum(line.startswith("file ") for line in manifest)
            print(f"overlay: {files} files added to {args.tree}, conf/abi.xml extended; now run: "
                  f"make -C {args.tree} static_h")
        else:
            changed = remove(args.tree)
            for rel in changed:
                print(f"overlay: left {rel}: changed since install", file=sys.stderr)
            print(f"overlay: removed from {args.tree}; now run: make -C {args.tree} static_h")
    except (OverlayError, OSError) as err:
        print(f"overlay: error: {err}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
