"""``run_rows`` where modules converted before runtime.fast existed import it
from (runtime.contract: a module converted before keeps working); modules
converted now import it from runtime.fast."""

from runtime.fast.rows import run_rows

__all__ = ["run_rows"]
