"""The statistics of the last frame rendered (F12 or viewport), for the panels."""

_last = {}


def last_stats():
    return _last


def remember(stats):
    _last.clear()
    _last.update(stats)


def forget():
    _last.clear()
