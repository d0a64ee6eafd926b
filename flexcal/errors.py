"""Errors a user can fix. The CLI prints them as one line, without a traceback."""


class FlexcalError(Exception):
    """Bad input at a boundary (file, port, argument); the message names it and the fix."""
