#!/usr/bin/env python3
"""`make paparazzi-check`: build and fly our modules in the Paparazzi tree $PAPARAZZI_HOME, on a scratch copy.

Usage: PAPARAZZI_HOME=<tree> tools/paparazzi_check.py [--out build/paparazzi] [--duration 60] [--time-factor 10]
Steps and checks: tools/finken/paparazzi/check.py.
"""
import sys

from finken.paparazzi.check import main

if __name__ == "__main__":
    sys.exit(main())
