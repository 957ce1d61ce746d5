"""Exceptions that the command line turns into exit statuses."""


class SceneError(ValueError):
    """A rejected input: the message is one line naming the key or block at fault.

    The command line prints it on stderr and exits with status 2.
    """

    def __init__(self, message: str):
        super().__init__(" ".join(str(message).split()))


class SceneWarning(UserWarning):
    """A scene accepted with a doubt, e.g. a key its schema does not know (shown on stderr;
    ``--strict`` turns it into a SceneError)."""


class SolverError(RuntimeError):
    """A solver run that could not produce a trustworthy answer (exit status 1)."""
