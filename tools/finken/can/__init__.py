"""The ranging units on CAN (docs/drivers.md), through the C code the Linux driver runs (_native, cffi).

    ranging_frame      the ranging frame: decoding and validation
    candump            can-utils candump -l logs, one frame per line
    candump_rangelog   a candump log and motion-capture poses to a range log (tools/candump_to_rangelog.py)
"""
