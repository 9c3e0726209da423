"""A stage's result kept with the key of what it depends on, made again when that changes."""


class KeyedCache:
    """One value and the key it was made for (None: nothing, or forgotten); with
    `releases`, a value replaced or cleared is released (its GPU memory freed)."""

    def __init__(self, releases=False):
        self.releases = releases
        self.key = None
        self.value = None

    def get(self, key, make):
        """The value for `key`: the one held when made for it, else `make()`'s, the old
        one released first (a driver may refuse the new one while both are held)."""
        if self.value is None or self.key != key:
            self.clear()
            self.value = make()
            self.key = key
        return self.value

    def put(self, key, value):
        """Hold `value` for `key`, releasing the old value unless it is `value` again."""
        if self.releases and self.value is not None and self.value is not value:
            self.value.release()
        self.key, self.value = key, value

    def forget(self):
        """Forget what the value was made for, keeping the value (and its memory)."""
        self.key = None

    def clear(self):
        if self.releases and self.value is not None:
            self.value.release()
        self.key = self.value = None
