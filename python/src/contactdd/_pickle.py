"""Pickling of ``ContactddIOError``.

The other classes pickle by themselves: problems as their problem file text, results as their
attributes (``__reduce__`` of the extension's classes), ``ContactddError`` and
``ConvergenceError`` as Python exceptions do (class, message, and ``result`` in ``__dict__``).
An ``OSError`` pickles its ``errno`` only when it was made as ``OSError(errno, strerror)``, which
would change the message of ``ContactddIOError``; so it gets its own ``__reduce__``.
"""

from ._contactdd import ContactddIOError


def _restore_io_error(cls, args, errno, state):
    """Rebuilds a ``ContactddIOError`` pickled by :func:`_reduce_io_error`."""
    error = cls(*args)
    error.errno = errno
    error.__dict__.update(state)
    return error


def _reduce_io_error(self):
    return (_restore_io_error, (type(self), self.args, self.errno, dict(self.__dict__)))


ContactddIOError.__reduce__ = _reduce_io_error
