#!/usr/bin/env python3
"""`make paparazzi-sim`: a FINken swarm in Paparazzi's NPS (one process per aircraft), detector on and off, merged
logs and the report of `make sim`; the tree $PAPARAZZI_HOME is only read (a scratch copy is built).

Usage: PAPARAZZI_HOME=<tree> tools/paparazzi_sim.py [--out build/paparazzi-sim] [--vehicles 4] [--duration 180]
       [--time-factor 1] [--seed 1] [--gcs] [--pose-rate HZ] [--sensor-model MODEL.xml]
Steps: tools/finken/paparazzi/sim.py.
"""
import sys

from finken.paparazzi.sim import main

if __name__ == "__main__":
    sys.exit(main())
