"""The one exception type for errors a user can cause and fix."""


class LPVError(Exception):
    """A problem the user can fix; its message is one sentence that says what to do.

    Blender shows it in the status bar and the command line prints it without a traceback.
    """
