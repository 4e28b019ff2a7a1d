"""make bench (tools/bench.py; docs/performance.md): speed, scale and memory, each against a peer in the same run.

    programs                    the C benchmark programs of tests/bench/ and their figures
    host, arena                 whole runs of our host, in arenas scaled to the swarm size
    gmr_peer                    the Python gmr package, the peer of our mixture sampler
    sweep                       the sweep engine on 1 and 2 workers
    paparazzi, paparazzi_figures   our world's cost in Paparazzi's NPS
    report                      derived ratios, targets, the table and build/bench.json
"""
