"""The bundled sloping site as a case dict for the slope tests, without plots, with edits given
as ``section__key=value``."""
from twofluid.casefile.loader import load_case

CASE = "sloping-site"


def sloping_case(**edits):
    c = load_case(CASE)
    c["output"]["plots"] = False
    for k, v in edits.items():
        sec, key = k.split("__")
        c[sec][key] = v
    return c
