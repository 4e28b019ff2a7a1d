#!/usr/bin/env python3
"""`make paparazzi-ivy-race`: several Paparazzi NPS processes on one Ivy bus crash; this shows why
(tools/finken/paparazzi/ivy_race.py, tests/paparazzi/ivy_two_threads.c; docs/paparazzi.md, "One Ivy bus per aircraft").
"""
import sys

from finken.paparazzi.ivy_race import main

if __name__ == "__main__":
    sys.exit(main())
