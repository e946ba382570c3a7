"""The one place tests make an OpenGL context: headless (EGL), shared by the session."""

from __future__ import annotations

import pytest


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
