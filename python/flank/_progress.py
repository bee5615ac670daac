"""Progress of long calls: the library's events (``flank::progress``:
``ltca positions``, ``fe positions``, ``campaign jobs``) passed to a
callback, or drawn as tqdm bars when tqdm is installed."""

from __future__ import annotations

from typing import Any, Callable, Optional, Union

__all__ = ["ProgressCallback", "TqdmProgress", "resolve"]

#: ``callback(task, done, total)``: ``done`` of ``total`` steps of the
#: stage ``task`` (``total`` may grow while the stage runs).
ProgressCallback = Callable[[str, int, int], None]


class TqdmProgress:
    """A tqdm bar per stage: a new bar when the stage changes or starts
    again (``done == 0``), closed when it reaches its total."""

    def __init__(self, **tqdm_kwargs: Any):
        from tqdm.auto import tqdm

        self._tqdm = tqdm
        self._kwargs = tqdm_kwargs
        self._bar = None
        self._task: Optional[str] = None

    def __call__(self, task: str, done: int, total: int) -> None:
        if self._bar is None or task != self._task or done == 0:
            self.close()
            self._bar = self._tqdm(total=total, desc=task, unit="step", **self._kwargs)
            self._task = task
        bar = self._bar
        if bar.total != total:
            bar.total = total
        # events of parallel steps may arrive out of order: the bar never goes back
        if done > bar.n:
            bar.update(done - bar.n)
        if done >= total:
            self.close()

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None
            self._task = None


def resolve(progress: Union[None, bool, ProgressCallback], quiet: bool) -> Optional[ProgressCallback]:
    """The callback for ``progress``: a callable as given; ``True``: tqdm
    bars (ImportError without tqdm); ``False``: none; ``None`` (the
    default): tqdm bars when tqdm is installed and ``quiet`` is false, else
    none."""
    if progress is False:
        return None
    if progress is True:
        return TqdmProgress()
    if progress is None:
        if quiet:
            return None
        try:
            return TqdmProgress()
        except ImportError:
            return None
    if not callable(progress):
        raise TypeError(f"progress={progress!r}: a callable (task, done, total), True, False or None")
    return progress
