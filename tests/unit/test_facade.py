"""The public facade: every exported name resolves, unknown names fail."""
import pytest

import twofluid


@pytest.mark.parametrize("name", twofluid.__all__)
def test_exported_name_resolves(name):
    assert getattr(twofluid, name) is not None


def test_unknown_name_is_an_attribute_error():
    with pytest.raises(AttributeError):
        twofluid.no_such_thing  # noqa: B018
