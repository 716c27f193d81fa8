"""Not collected by the suite (not test_*.py): test_refuse_skips.py runs it in a child pytest to
show that THICKET_REFUSE_SKIPS=1 fails a skipped test."""

import pytest


def test_that_skips():
    pytest.skip("a planted skip")
