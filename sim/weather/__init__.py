"""The weather outside the window: a reading of the current conditions (`Reading`), the
glass between the room and the night (`glass_temperature`), and what that glass does to
the frost (`frost_of`, docs/method.md section 12). Pure Python: no numpy, GL or network."""

from .glass import (
    GLAZINGS,
    THAW_TICKS,
    Frost,
    Glass,
    describe,
    event_frost,
    event_words,
    frost_of,
    glass_temperature,
)
from .reading import Reading

__all__ = ["GLAZINGS", "THAW_TICKS", "Frost", "Glass", "Reading", "describe", "event_frost",
           "event_words", "frost_of", "glass_temperature"]
