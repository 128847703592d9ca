"""Captures of a serial link: what two stations put on the line, with timestamps, read and
written in four formats (capture JSON, a ``ptpcert run`` results object, the hex log, and
pcap for Wireshark). Procedure-neutral: it knows bytes and line conditions, no protocol.

The specification of the formats, times and line conditions is one document,
``docs/capture-formats.md``. The package along its jobs:

``model``           :class:`Capture`, :class:`Chunk`, :class:`Mark`, :class:`Cond`,
                    :class:`CaptureError`, and the text forms the formats share
``json_format``     capture JSON (:func:`to_dict`, :func:`from_dict`)
``results_format``  transcripts and results objects (:func:`from_transcript`,
                    :func:`to_transcript`, :func:`from_results`, :func:`to_results`)
``hexlog``          the hex log (:func:`read_hexlog`, :func:`write_hexlog`, :class:`HexLogWriter`)
``pcap``            pcap, LINKTYPE_RTAC_SERIAL (:func:`read_pcap`, :func:`write_pcap`,
                    :class:`PcapWriter`)
``timing``          how a capture's times were taken (:class:`Timing`, :func:`run_timing`)
``files``           formats by name or extension, :func:`load` and :func:`save`

The line settings a capture carries are :class:`ptpcert.model.line.LineSettings`. This
module is the package's face: it re-exports what the rest of ptpcert uses.
"""

from ptpcert.capture.files import EXTENSIONS, FORMATS, dumps, format_of, load, loads_json, save
from ptpcert.capture.hexlog import (HEXLOG_MAGIC, HEXLOG_VERSION, HexLogWriter, hexlog_text, parse_line,
                                    read_hexlog, write_hexlog)
from ptpcert.capture.json_format import (JSON_FORMAT, LINE_DEFAULTS, chunk_to_dict, from_dict, line_from_dict,
                                         line_to_dict, to_dict)
from ptpcert.capture.model import (GAPS, LINE_ALIASES, MODEM_LINES, SEATS, WITH_DATA, Capture, CaptureError, Chunk,
                                   Cond, Mark, capture_time, checked_line, hex_text, iso_time, parse_start)
from ptpcert.capture.pcap import (EPOCH, EV_CAPTURE_COMPLETE, EV_CAPTURE_DATA_LOST, EV_DATA_RX_END, EV_DATA_RX_START,
                                  EV_DATA_TX_END, EV_DATA_TX_START, EV_FRAMING_ERROR, EV_PARITY_ERROR,
                                  EV_SERIAL_BREAK, EV_SERIAL_OVERFLOW, EV_STATUS_CHANGE, LINKTYPE_RTAC_SERIAL,
                                  MARK_TAG, MAX_PAYLOAD, PCAP_MAGIC_NS, PCAP_MAGIC_US, PCAPNG_MAGIC, RTAC_HEADER,
                                  SNAPLEN, START_TAG, PcapWriter, pcap_bytes, read_pcap, write_pcap)
from ptpcert.capture.results_format import (CAPTURE_GROUP, CASE_GAP, PARAMS_TAG, PROCEDURE_NOTE, RUN_SEATS,
                                            TRANSCRIPT_DIR, from_results, from_transcript, params_text, to_results,
                                            to_transcript)
from ptpcert.capture.timing import TRANSPORTS, Timing, run_timing
from ptpcert.model.line import LineSettings

__all__ = [
    # model
    "Capture", "CaptureError", "Chunk", "Cond", "GAPS", "LINE_ALIASES", "LineSettings", "MODEM_LINES", "Mark",
    "SEATS", "WITH_DATA", "capture_time", "checked_line", "hex_text", "iso_time", "parse_start",
    # capture JSON
    "JSON_FORMAT", "LINE_DEFAULTS", "chunk_to_dict", "from_dict", "line_from_dict", "line_to_dict", "to_dict",
    # transcripts and results objects
    "CAPTURE_GROUP", "CASE_GAP", "PARAMS_TAG", "PROCEDURE_NOTE", "RUN_SEATS", "TRANSCRIPT_DIR", "from_results",
    "from_transcript", "params_text", "to_results", "to_transcript",
    # hex log
    "HEXLOG_MAGIC", "HEXLOG_VERSION", "HexLogWriter", "hexlog_text", "parse_line", "read_hexlog", "write_hexlog",
    # pcap
    "EPOCH", "EV_CAPTURE_COMPLETE", "EV_CAPTURE_DATA_LOST", "EV_DATA_RX_END", "EV_DATA_RX_START", "EV_DATA_TX_END",
    "EV_DATA_TX_START", "EV_FRAMING_ERROR", "EV_PARITY_ERROR", "EV_SERIAL_BREAK", "EV_SERIAL_OVERFLOW",
    "EV_STATUS_CHANGE", "LINKTYPE_RTAC_SERIAL", "MARK_TAG", "MAX_PAYLOAD", "PCAPNG_MAGIC", "PCAP_MAGIC_NS",
    "PCAP_MAGIC_US",
    "PcapWriter", "RTAC_HEADER", "SNAPLEN", "START_TAG", "pcap_bytes", "read_pcap", "write_pcap",
    # timing
    "TRANSPORTS", "Timing", "run_timing",
    # files
    "EXTENSIONS", "FORMATS", "dumps", "format_of", "load", "loads_json", "save",
]
