"""The one place tests make an OpenGL context: headless (EGL), shared by the session."""

from __future__ import annotations

import pytest
from hypothesis import settings

# No example database: tests never write into the checkout (.hypothesis/). No deadline:
# the machine is shared and loaded; speed is the benchmarks' business.
settings.register_profile("frost", database=None, deadline=None)
settings.load_profile("frost")


@pytest.fixture(scope="session")
def gl_ctx():
    """A standalone OpenGL context; GL tests skip cleanly where none can be made."""
    from app.headless import make_context

    try:
        ctx = make_context()
    except RuntimeError as err:
        pytest.skip(str(err))
    yield ctx
    ctx.release()
