"""massline.uff — Universal Files as modal test software writes them, read and written.

:func:`~.reader.read_uff` and :func:`~.grid.to_recording` read nodes (15/2411), coordinate systems
(18/2420), units (164) and FRFs with their coherence (58/58b; accelerance, mobility or receptance,
:mod:`.frf_kind`) from any exporter's file (:mod:`.datasets` splits and parses it);
:func:`~.writer.write_uff` writes a :class:`~.recording.Recording` the same way, with nodes and
direction codes from :mod:`.layout`, in the unit systems of :mod:`.units` (SI, mm, in; g/N). A channel is a :class:`~.recording.Channel`: a node and a
direction code.
"""

from massline.uff.grid import to_recording
from massline.uff.reader import read_uff
from massline.uff.recording import Channel, Recording
from massline.uff.writer import write_uff

__all__ = ["Channel", "Recording", "read_uff", "to_recording", "write_uff"]
