"""The library's exceptions, and the one mapping of exceptions to exit statuses (run_command)."""


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
    """A step that ended "failed": raised only by :meth:`limit.api.Result.raise_for_status`, for a
    script that needs a trustworthy number. The analysis and the command line report a failed step
    as a status instead (``limit solve`` exits 1); escaping a command, it is exit status 1 too."""


def run_command(command, debug_env: str = "LIMIT_DEBUG") -> int:
    """Run ``command()`` (which returns an exit status) and turn an escaping exception into
    the exit status of docs/formats.md, 'Commands' -- the one mapping of every command line
    (``limit``, ``python -m dem_validation``, ``python -m reports.vtk``):

    * SceneError: 2, the message as one line ``error: ...`` on stderr;
    * BrokenPipeError (e.g. piped into ``head``): 0;
    * KeyboardInterrupt: 130, ``interrupted`` on stderr;
    * any other Exception: 1, one line ``failed: Type: message`` on stderr, or re-raised
      (with its traceback) when the environment variable ``debug_env`` is set.
    """
    import os
    import sys

    try:
        return command()
    except SceneError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        return 0
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # an internal failure: one line, traceback on request
        if os.environ.get(debug_env):
            raise
        print(f"failed: {type(exc).__name__}: {exc} (set {debug_env}=1 for a traceback)", file=sys.stderr)
        return 1
