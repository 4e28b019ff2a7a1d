"""A lab's flight to a range log: readers of the copter's records and of motion capture, the clock offset, the true
ranges (command line: tools/flight_rangelog.py).

    errors    FlightInputError: a file a reader cannot use, `file:line: reason` (line 1 = header)
    csv_table   a small CSV with a header row, its columns as text, numbers or ids (Table, read_table)
    server_log  Paparazzi's server log (.log/.data): the message definitions (the .log's, else BUILTIN_MESSAGES)
              and the lines of the messages asked for (ServerLog, Messages, Field, field_values)
    records   the copter's records of every sensor reading: a CSV in the range-log columns, or Paparazzi's server
              log with FINKEN_RANGE_READING and FINKEN_WALL_DECISION (stamps unwrapped, time order checked); the
              recorder's decisions CSV
    motive    an OptiTrack Motive CSV export: each rigid body's positions and quaternions, as exported
    mocap     motion-capture poses: a plain CSV, our simulator's poses.csv, a Motive export, or the positions in
              Paparazzi's server log; bodies to vehicles, the frame transform, jumps and losses, poses interpolated
              at any time (Poses.at)
    clock     each copter's clock offset to the motion capture's, from the readings and the poses
    mounts    where the sonars sit on the copter (from the airframe or the arena file)
    truth     the true range of each reading and the context columns, from the poses and the arena
    flight_log  the whole flight to a range log: bodies checked, clocks put on the motion capture's, truth
    loop      the loop closed on a simulated flight: the recorders' files as a lab's, the computed truth against
              the simulator's

Readers write nothing. Units: SI (s, m, rad); quaternions scalar last (qx, qy, qz, qw) turning the body frame
(x forward, y left, z up) into the arena frame (x east, y north, z up).
"""
