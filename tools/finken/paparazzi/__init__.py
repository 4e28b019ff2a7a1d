"""Our modules in a real Paparazzi tree (docs/paparazzi.md).

    overlay        lay our files over a tree and take them off, never replacing one of Paparazzi's
    tree           a scratch copy of a tree with the overlay, its environment, Paparazzi's own make on it
    check, flight_check, swarm_check, loop_check, obstacle_check   make paparazzi-check: build, fly one aircraft, fly a
                   swarm in one world, close the loop from a flight's records to a calibrated model, fly a swarm
                   in an arena with a pillar
    swarm_conf, sim, aircraft_logs     make paparazzi-sim: the conf and airframes, the NPS processes, their logs
    fleet          child processes side by side, one per aircraft
    ground         Paparazzi's ground segment beside a simulated swarm
    ground_check, ground_commands   make paparazzi-check: what the ground segment sees of the swarm, commands
    gcs_view       PprzGCS on a virtual display, and its picture of the swarm
    arena_shapes   the arena's walls and obstacles drawn on the GCS (SHAPE messages)
    session        a Paparazzi Center session read as the Center reads it
    ground_ports   whether the data link's UDP port and an Ivy bus are free
    ivy_race       why several NPS processes on one Ivy bus crash, reproduced
"""
