"""The ``capture`` command: convert a recorded link between ptpcert's capture formats; where
the Wireshark dissector is, and installing it."""

from __future__ import annotations

import os
import sys


def add_commands(sub) -> None:
    from ptpcert.capture import FORMATS

    cap = sub.add_parser("capture", help="convert captures of a serial link (transcript, hex log, pcap); "
                                         "the Wireshark dissector",
                         description="Work with captures of a serial link: ptpcert's transcripts "
                                     "(results.json), capture JSON, the hex log and pcap for Wireshark. "
                                     "--wireshark-plugin prints where ptpcert's Wireshark dissector (Lua) is; "
                                     "--wireshark-plugin install copies it into the personal Lua plugin "
                                     "folder (or --plugin-dir). Exit status: 0 done, 2 on any error.")
    cap.add_argument("--wireshark-plugin", nargs="?", const="where", metavar="install",
                     help="print the path of the Wireshark dissector (ptpcert.lua); with 'install': copy it "
                          "into Wireshark's personal Lua plugin folder (~/.local/lib/wireshark/plugins)")
    cap.add_argument("--plugin-dir", metavar="DIR",
                     help="with --wireshark-plugin install: this folder instead of the personal plugin folder")
    csub = cap.add_subparsers(dest="capture_command", metavar="SUBCOMMAND")
    conv = csub.add_parser(
        "convert", help="convert a capture from one format to another",
        description="Convert a capture. The formats come from the extensions (.json: capture JSON, or a "
                    "results object when it is one; .hexlog/.log/.txt: hex log; .pcap: pcap with link "
                    "type RTAC serial, for Wireshark) or from --from/--to. OUT '-' writes to standard "
                    "output (default format there: hexlog). Exit status: 0 converted, 2 on any error.")
    conv.add_argument("input", metavar="IN", help="the capture to read")
    conv.add_argument("output", metavar="OUT", help="the file to write, or - for standard output")
    conv.add_argument("--from", dest="from_", choices=FORMATS, metavar="FMT",
                      help=f"the input's format ({', '.join(FORMATS)})")
    conv.add_argument("--to", choices=FORMATS, metavar="FMT", help=f"the output's format ({', '.join(FORMATS)})")
    conv.add_argument("--case", metavar="ID",
                      help="from a results object: this case only (default: the whole run on one timeline)")
    conv.set_defaults(func=cmd_convert)
    cap.set_defaults(func=lambda args: _no_subcommand(cap, args))


def _no_subcommand(parser, args) -> int:
    if args.wireshark_plugin is not None or args.plugin_dir is not None:
        return cmd_wireshark_plugin(args)
    parser.print_usage(sys.stderr)
    print("ptpcert capture: give a subcommand (convert) or --wireshark-plugin", file=sys.stderr)
    return 2


def cmd_wireshark_plugin(args) -> int:
    from ptpcert.capture import CaptureError
    from ptpcert.capture.wireshark_plugin import install_plugin, personal_plugin_dir, plugin_path

    how = args.wireshark_plugin
    if how not in ("where", "install"):
        what = "--plugin-dir needs --wireshark-plugin install" if how is None else (
            f"--wireshark-plugin {how}: give nothing (print where the dissector is) or 'install'")
        print(f"ptpcert capture: {what}", file=sys.stderr)
        return 2
    if how == "where":
        if args.plugin_dir is not None:
            print("ptpcert capture: --plugin-dir needs --wireshark-plugin install", file=sys.stderr)
            return 2
        print(plugin_path())
        return 0
    try:
        target, how = install_plugin(args.plugin_dir)
    except CaptureError as exc:
        print(f"ptpcert capture: {exc}", file=sys.stderr)
        return 2
    said = {"installed": "installed", "replaced": "installed, replacing another copy",
            "unchanged": "already installed, unchanged"}[how]
    print(f"{target}: {said}; Wireshark loads it at its next start (Help > About Wireshark > Plugins lists it)")
    if args.plugin_dir is not None and os.path.realpath(args.plugin_dir) != os.path.realpath(personal_plugin_dir()):
        print(f"not Wireshark's personal plugin folder ({personal_plugin_dir()}): load it with "
              f"-X lua_script:{target}")
    return 0


def cmd_convert(args) -> int:
    from ptpcert import capture as C

    from ptpcert.results import report_path_problem

    if args.output != "-":   # before anything is read: never a device, never the input
        same = os.path.realpath(args.output) == os.path.realpath(args.input)
        problem = "is also the input; give the output its own file" if same else report_path_problem(args.output)
        if problem:
            print(f"ptpcert capture: {args.output}: {problem}", file=sys.stderr)
            return 2
    try:
        cap = C.load(args.input, args.from_, args.case)
        if args.output == "-":
            data = C.dumps(cap, args.to or "hexlog", args.case or "capture")
            out = sys.stdout.buffer
            out.write(data)
            out.flush()
            return 0
        C.save(cap, args.output, args.to, args.case or "capture")
    except C.CaptureError as exc:
        print(f"ptpcert capture: {exc}", file=sys.stderr)
        return 2
    n = len(cap.chunks)
    print(f"{args.output}: {n} chunk{'s' if n != 1 else ''}, {cap.duration:.6f} s")
    return 0
