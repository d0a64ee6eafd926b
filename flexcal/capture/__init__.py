"""The edge to hardware and files: serial lines, logs, frames, trial folders."""

from flexcal.capture.protocol import BAUD, HEADER, format_sample, parse_line

__all__ = ["BAUD", "HEADER", "format_sample", "parse_line"]
