"""Imported first by every figure module of :mod:`twofluid.plots`: in the ``twofluid`` command's
own process (:func:`twofluid.plots.command_process`), matplotlib's first import is the lean one
(:func:`twofluid.plots.import_matplotlib_lean`); elsewhere nothing happens here."""
from . import import_matplotlib_lean, is_command_process

if is_command_process():
    import_matplotlib_lean()
