"""The one exception type for errors a user can cause and fix."""


class LPVError(Exception):
    """A problem the user can fix; its message is one sentence that says what to do.

    Blender shows it in the status bar and the command line prints it without a traceback.
    """


def first_line(error):
    """An exception's first line without its full stop (its type's name when it says
    nothing): the reason inside one of our sentences."""
    text = str(error).strip()
    return text.splitlines()[0].rstrip(".") if text else type(error).__name__
