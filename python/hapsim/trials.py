"""Trials and their automatic metrics (SessionService.GetTrials) as typed rows.

The server sends CSV (columns: docs/classroom.md, "Trials and their
automatic metrics"); a row here has the same columns, in the same order, as
``hapsim-ctl trials --csv``, with numbers as numbers and blanks as None.
"""
import csv
import dataclasses
import io
from dataclasses import dataclass
from typing import Callable, Dict, List, Optional, Tuple

from .errors import ProtocolError


def _number(text: str) -> Optional[float]:
    return float(text) if text != "" else None


def _layers(text: str) -> Tuple[str, ...]:
    return tuple(text.split("+")) if text else ()


def _forces_by_layer(text: str) -> Dict[str, float]:
    # "skin=0.9948;fat=0.2010;muscle=1.4555"
    out: Dict[str, float] = {}
    for item in filter(None, text.split(";")):
        layer, _, force = item.partition("=")
        out[layer] = float(force)
    return out


@dataclass(frozen=True)
class TrialRow:
    """One trial: from a session's creation or reset to its next reset or close."""

    session: str
    trainee: str
    scene: str
    trial: int                               # 0, 1, ... per session
    end: str                                 # reset | closed | running
    duration_s: Optional[float]              # sim time of the trial [s]
    time_to_contact_s: Optional[float]       # to the first contact [s]; None: no contact
    peak_force_N: Optional[float]            # largest |force on the tool| [N]
    max_depth_mm: Optional[float]            # deepest tip below the surface [mm]
    target_depth_mm: Optional[float]         # the class's target [mm]; None: no target
    depth_error_mm: Optional[float]          # max depth - target [mm]; None: no target or no contact
    layers_pierced: Tuple[str, ...]          # layers with a puncture, e.g. ("skin", "fat")
    punctures: int
    peak_force_by_layer_N: Dict[str, float]  # largest force in or on each layer [N]
    incisions: int                           # cut_end events
    incision_length_mm: Optional[float]      # their summed length [mm]
    line_deviation_max_mm: Optional[float]   # while cutting, from the target line [mm]; None: no line
    line_deviation_mean_mm: Optional[float]  # [mm]
    score: Optional[float]                   # the session's expert score so far; None: unscored

    @staticmethod
    def columns() -> List[str]:
        """The CSV's column names, in order."""
        return [f.name for f in dataclasses.fields(TrialRow)]


_PARSERS: Dict[str, Callable[[str], object]] = {
    "trial": int, "punctures": int, "incisions": int,
    "layers_pierced": _layers, "peak_force_by_layer_N": _forces_by_layer,
    "session": str, "trainee": str, "scene": str, "end": str,
}


def parse_trials_csv(text: str) -> List[TrialRow]:
    """Rows of the server's trials CSV; columns it adds later are ignored."""
    reader = csv.DictReader(io.StringIO(text))
    missing = [c for c in TrialRow.columns() if c not in (reader.fieldnames or [])]
    if missing:
        raise ProtocolError(None, f"trials CSV lacks columns {missing} (header: {reader.fieldnames})")
    rows = []
    for record in reader:
        try:
            rows.append(TrialRow(**{c: _PARSERS.get(c, _number)(record[c]) for c in TrialRow.columns()}))
        except (TypeError, ValueError) as error:
            raise ProtocolError(None, f"bad trials CSV row {record}: {error}") from None
    return rows
