"""Test sequences, format railbrake.sequence/1 (docs/sequences.md): tests of steps run against the
plant (set demand, set the adhesion, inject or clear a fault, wait, expect a condition within a time
window, record a KPI), each with a verdict, reported as JUnit XML and HTML.

railbrake.sequence.schema reads and checks a sequence file; .engine runs it, .reports writes
the reports. Every error names the file, the line and the key."""

from railbrake.sequence.schema import (CHANNEL_DIMENSION, COMPARISONS, FORMAT, MAX_STEPS, MAX_TESTS, UNITS,
                                       Condition, Demand, Expect, RecordKpi, Sequence, SequenceFile, Step, Test,
                                       Threshold, WaitAt, WaitUntil, duration, load, matching, parse, presets,
                                       quantity)

__all__ = ["CHANNEL_DIMENSION", "COMPARISONS", "FORMAT", "MAX_STEPS", "MAX_TESTS", "UNITS", "Condition", "Demand",
           "Expect", "RecordKpi", "Sequence", "SequenceFile", "Step", "Test", "Threshold", "WaitAt", "WaitUntil",
           "duration", "load", "matching", "parse", "presets", "quantity"]
