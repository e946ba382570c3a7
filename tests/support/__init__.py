"""What the test modules share, by job: no test module imports another. The modules here
are imported as `support.<job>` (pytest puts tests/ on the path, as does a test file run
as a script under Xvfb)."""

from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent.parent
