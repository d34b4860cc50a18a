"""The command line, `python simulator.py [flags]` (docs/command-line.md): a scene flag sets one
parameter of the scenes whose mapping (scene_kinds) has it; one may take a list, one run per value.
A bad command line is one line naming the flag, exit code 2."""
import argparse
import dataclasses
import math
import re

import simulator
import utils
from scenes import UNITS, ranges, tablecloth
from viewer.command import run

DURATION = 6.0          # s: long enough to see mu = 0.11 stick (about 5.5 s), and creep
CHALK_DURATION = 3.0    # s: about 17 stick-slip cycles of the pushed chalk
STOP_MARGIN = 0.05      # s a tablecloth run goes on after its slowest closed-form dish has stopped
FRAMES_PER_SECOND = 30      # at least this many frames per simulated second by default
LABEL = {"square": "mu = {mu:g}", "chalk": "{how}, mu_s = {mu_s:g}, mu = {mu:g}",
         "tablecloth": "pull-speed = {pull_speed:g}, mu = {mu:g}",
         **{kind: unit.LABEL for kind, unit in UNITS.items()}}      # a single run's label

# (flags, parameter, metavar, what it is): the square's scene flags, the chalk's, the tablecloth's,
# then those the scene units declare (scenes.UNITS)
FLAGS = [
    (("--mu",), "mu", "MU", "friction coefficient, no unit"),
    (("--h", "--dt"), "h", "SECONDS", "time step in s"),
    (("--n-seg",), "n_seg", "N", "segments per side of the square"),
    (("--side",), "side_len", "METRES", "side length of the square in m"),
    (("--k",), "k", "N_PER_M", "spring stiffness in N/m"),
    (("--density",), "rho", "KG_PER_M2", "density in kg/m^2"),
    (("--mass",), "mass", "KG", "total mass in kg, instead of --density"),
    (("--slope-normal",), "slope", "NX,NY", "the slope's normal, normalized for you"),
    (("--slope-point",), "slope_point", "OX,OY", "a point on the slope in m"),
    (("--center",), "center", "X,Y", "initial centre of the square in m"),
    (("--v0",), "v0", "VX,VY", "initial velocity in m/s"),
    (("--gravity",), "gravity", "GX,GY", "gravity in m/s^2"),
    (("--dhat",), "dhat", "METRES", "barrier activation distance in m"),
    (("--kappa",), "kappa", "KAPPA", "barrier stiffness in N/m (P_b = sum of w dhat b(d), in J)"),
    (("--epsv",), "epsv", "M_PER_S", "friction's eps_v in m/s"),
    (("--tol",), "tol", "M_PER_S", "Newton tolerance on ||p||_inf / h in m/s"),
    (("--friction-iterations",), "friction_updates", "N",
     "fixed-point friction updates per step, fully implicit friction (Algorithm 5); 0: lagged"),
    (("--max-newton",), "max_newton_iterations", "N", "Newton iteration cap per solve"),
    (("--newton-start",), "newton_start", "START", "where each step's Newton starts: x_n, as the "
     "lecture, or x_tilde = x^n + h v^n cut back by CCD"),
    (("--tilt",), "tilt", "DEG", "--scene chalk: the chalk's angle from the board in degrees"),
    (("--grip",), "k_hand", "N_PER_M", "--scene chalk: grip stiffness per held node in N/m"),
    (("--mu-static",), "mu_s", "MU",
     "--scene chalk: static friction coefficient (equal to --mu: one coefficient)"),
    (("--pull-speed",), "pull_speed", "M_PER_S", "--scene tablecloth: the cloth's speed U in m/s"),
    (("--pull-length",), "pull_length", "METRES", "--scene tablecloth: the pull's length L in m"),
]  + [flag for unit in UNITS.values() for flag in unit.FLAGS]
FLAG_OF = {param: flags[0] for flags, param, _, _ in FLAGS}     # a ValueError's parameter -> flag
FLAG_OF.update({name: "--" + name.replace("_", "-") for name in
                ("slope_angle", "steps", "duration", "frame-stride", "out", "size", "speed")})
PAIR = {param for _, param, metavar, _ in FLAGS if "," in metavar}
COUNT = {param for _, param, metavar, _ in FLAGS if metavar == "N"}


class CommandLineError(Exception):
    """A bad command line: reported in one line, exit code 2."""


class Parser(argparse.ArgumentParser):
    def error(self, message):
        raise CommandLineError(message)


def pair(text):
    """'X,Y' as two floats."""
    try:
        values = tuple(float(s) for s in text.replace(",", " ").split())
    except ValueError:
        values = ()
    if len(values) != 2:
        raise argparse.ArgumentTypeError(f"expected two numbers 'X,Y', got {text!r}")
    return values


def whole(text):
    """A count (N) as a float, checked to be whole where the scene or the run is built."""
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"invalid int value: {text!r}") from None


def shown(value):
    """A default as --help shows it."""
    if isinstance(value, tuple):
        return ",".join(f"{v:g}" for v in value)
    if value is None:
        return "density x side^2"
    return value if isinstance(value, str) else f"{value:g}"


def default_words(param):
    """A scene flag's default as --help shows it: the first scene's with it, then each other
    scene's where it differs ('0.11; chalk 0.35, tablecloth 0.2')."""
    values = [(kind, table[param]) for kind, (table, _) in scene_kinds().items() if param in table]
    others = [f"{kind} {shown(value)}" for kind, value in values[1:] if value != values[0][1]]
    return shown(values[0][1]) + (f"; {', '.join(others)}" if others else "")


def make_parser():
    ap = Parser(prog="simulator.py", allow_abbrev=False, description=(
        "Simulate the lecture's elastic square on a slope (or --scene chalk, tablecloth"
        + "".join(f", {kind}" for kind in UNITS) + ") into a folder: frames, OBJs, log.csv, "
        "plots.png, summary.png and index.html, a page that plays the run. One scene flag may "
        "take a list, e.g. --mu 0.1,0.11,0.2: one run per value, compared (docs/command-line.md)."))
    g = ap.add_argument_group("scene (the lecture's numbers by default)")
    g.add_argument("--scene", choices=("square", "chalk", "tablecloth", *UNITS), default="square",
                   help="square: the lecture's square on a slope (default); chalk: Rabinowicz's "
                        f"chalk pushed across a board ({CHALK_DURATION:g} s); tablecloth: a dish "
                        "on a cloth pulled from under it (until the dish stops)" + "".join(
                            f"; {kind}: {unit.HELP} ({unit.DURATION:g} s)"
                            for kind, unit in UNITS.items()))
    for flags, param, metavar, what in FLAGS:
        default = default_words(param)
        kind = ({"choices": utils.NEWTON_STARTS} if param == "newton_start" else
                {"type": pair if param in PAIR else whole if param in COUNT else float})
        g.add_argument(*flags, dest=param, metavar=metavar, default=argparse.SUPPRESS,
                       help=f"{what} (default {default})", **kind)
    g.add_argument("--slope-angle", type=float, metavar="DEGREES", help="slope angle in degrees, "
                   "descending to the right, instead of --slope-normal")
    g.add_argument("--no-slope", action="store_true", help="free fall: no slope, no contact")
    g.add_argument("--drag", action="store_true",
                   help="--scene chalk: drag the chalk (acute angle) instead of pushing it")
    r = ap.add_argument_group("run and output")
    r.add_argument("--duration", type=float, metavar="SECONDS",
                   help=f"simulated seconds (default: the square {DURATION:g}, the chalk "
                        f"{CHALK_DURATION:g}" + "".join(f", the {kind} {unit.DURATION:g}"
                                                         for kind, unit in UNITS.items())
                        + f", the tablecloth until its closed-form dish stops, +{STOP_MARGIN:g})")
    r.add_argument("--steps", type=whole, metavar="N", help="time steps, instead of --duration")
    r.add_argument("--out", metavar="FOLDER", help="a new or empty folder to write into (default: "
                   "a new one, output/<scene>-<date>-<time>; with --window, files only when given)")
    r.add_argument("--frame-stride", type=whole, metavar="N", help="write a frame every N steps "
                   f"(default: {FRAMES_PER_SECOND} or more a simulated second)")
    r.add_argument("--no-forces", action="store_true", help="draw no force arrows in the frames")
    r.add_argument("--no-frames", action="store_true", help="write only log.csv, plots.png and "
                   "summary.png (no frames, OBJs or index.html)")
    r.add_argument("--window", action="store_true", help="run live in a window (docs/live-demo.md)")
    r.add_argument("--size", type=float, metavar="PIXELS",
                   help="--window: its side in pixels (default: fit the display)")
    r.add_argument("--speed", type=float, metavar="FACTOR", help="--window: simulated seconds per "
                   "wall-clock second (default 1; 0.25: slow motion)")
    return ap


def attach_negative_values(argv):
    """['--k', '-2e4'] -> ['--k=-2e4']: a token '-<digit, dot, inf or nan>' is a value, no flag."""
    out = []
    for token in argv:
        if (out and out[-1].startswith("--") and "=" not in out[-1]
                and re.match(r"^-([0-9.]|inf|nan)", token, re.I)):
            out[-1] = f"{out[-1]}={token}"
        else:
            out.append(token)
    return out


def parse_command_line(argv):
    """One argparse Namespace per run, with its `label`, file `tag` and `said` (decimal_comma)."""
    argv, parser = attach_negative_values(list(argv)), make_parser()
    param_of = {flag: param for flags, param, _, _ in FLAGS for flag in flags}
    uses = []           # (token index, flag, parameter, value) of each scene flag given
    for i, token in enumerate(argv):
        flag, joined, value = token.partition("=")
        if flag in param_of and (joined or i + 1 < len(argv)):
            uses.append((i, flag, param_of[flag], value if joined else argv[i + 1]))
    lists = [use for use in uses if (";" if use[2] in PAIR else ",") in use[3]]
    if not lists:
        args = parser.parse_args(argv)
        args.label, args.tag, args.said = "", "", None
        return [args]
    if len(lists) > 1:
        raise CommandLineError(f"only one scene flag may take a list of values, got "
                               f"{lists[0][1]} and {lists[1][1]}")
    i, flag, param, text = lists[0]
    again = [use[1] for use in uses if use[2] == param and use[0] != i]
    if again:
        raise CommandLineError(f"{flag}: given a list ({text}) and again as {again[0]}; give it "
                               f"once")
    is_pair = param in PAIR
    values = [v.replace(" ", "") for v in text.split(";" if is_pair else ",")]
    runs, rest, name = [], argv[i + (1 if "=" in argv[i] else 2):], flag.lstrip("-")
    said = decimal_comma(name, param, values)
    for value in values:
        args = parser.parse_args(argv[:i] + [f"{flag}={value}"] + rest)
        args.label, args.said = f"{name} = {value}", said
        args.tag = f"{name}_{value.replace(',', '_')}" if is_pair else f"{name}{value}"
        runs.append(args)
    numbers = [getattr(args, param) for args in runs]       # as the flag parses them: 0.1 = 0.10
    for j, number in enumerate(numbers):
        if number in numbers[:j]:
            raise CommandLineError(f"{flag}: the list {text} repeats a value: "
                                   f"{values[numbers.index(number)]} and {values[j]} are equal")
    return runs


def decimal_comma(name, param, values):
    """The first line of a list that may be a decimal comma, else None: two whole numbers given to
    a flag of decimals, read both ways only where the list is unlikely as written, its first 0
    ('--mu 0,11') or its second with a leading 0 ('3,05'); '--pull-speed 3,6' is a comparison."""
    if (param in COUNT or param in PAIR or len(values) != 2
            or not all(re.fullmatch(r"-?[0-9]+", v) for v in values)
            or not (int(values[0]) == 0 or values[1].startswith("0"))):
        return None
    return (f"comparing {name} = {values[0]} and {name} = {values[1]} (a list; a decimal is "
            f"written {values[0]}.{values[1]})")


def scene_kinds():
    """Each --scene's parameter mapping and builder (looked up when called)."""
    return {"square": (simulator.DEFAULTS, simulator.build_scene),
            "chalk": (simulator.CHALK, simulator.build_chalk_scene),
            "tablecloth": (simulator.TABLECLOTH, simulator.build_tablecloth_scene),
            **{kind: (unit.PARAMS, unit.BUILD) for kind, unit in UNITS.items()}}


def scene_from_args(args):
    """The --scene built with the scene flags given; refused: a flag that scene does not have."""
    overrides = {param: getattr(args, param) for _, param, _, _ in FLAGS if hasattr(args, param)}
    slopes = {"--slope-normal": "slope" in overrides, "--slope-angle": args.slope_angle is not None,
              "--no-slope": args.no_slope}
    given = [flag for flag, on in slopes.items() if on]
    if len(given) > 1:
        raise CommandLineError(f"{given[0]} and {given[1]} both set the slope; give one")
    if args.no_slope:
        overrides["slope"] = None
    elif args.slope_angle is not None:
        if not -90.0 < args.slope_angle < 90.0:
            raise utils.ParameterError("slope_angle", f"slope-angle must be in (-90, 90) degrees, "
                                       f"got {args.slope_angle}")
        theta = math.radians(args.slope_angle)
        overrides["slope"] = (math.sin(theta), math.cos(theta))
    if args.drag:
        overrides["drag"] = True
    table, build = scene_kinds()[args.scene]
    for param in overrides:
        if param not in table:
            flag = given[0] if param == "slope" else FLAG_OF.get(param, "--drag")
            owners = ", ".join(name for name, (params, _) in scene_kinds().items()
                               if param in params)
            raise CommandLineError(f"{flag} applies only to --scene {owners} (not {args.scene})")
    return build(**overrides)


def default_duration(scenes, kind=None):
    """DURATION, CHALK_DURATION, a scene unit's DURATION (--scene `kind`), or STOP_MARGIN after the
    runs' last closed-form dish stops."""
    if kind in UNITS:
        return UNITS[kind].DURATION
    if scenes[0].surface is None:
        return CHALK_DURATION if scenes[0].hand else DURATION
    stops = [tablecloth.stop_time(s.surface.pull_speed, s.surface.pull_length, s.mu,
                                               s.surface.t_pull, -s.g[1]) for s in scenes]
    for scene, stop in zip(scenes, stops):
        if not stop + STOP_MARGIN <= ranges.MAX_STEPS * scene.h:
            p, grows = scene.params, {"pull_length": 1, "pull_speed": -1, "t_pull": 1, "h": -1}
            name = ranges.culprit(p, simulator.TABLECLOTH, grows)
            raise utils.ParameterError(name, f"{name} = {p[name]:g}: the dish stops at t = "
                                       f"{stop:.3g} s, more than {ranges.MAX_STEPS:.0e} steps "
                                       f"(give --duration or --steps)")
    return max(stops) + STOP_MARGIN


def steps_from_args(args, scene, duration):
    """--steps, or --duration (default `duration`) in steps of h; either refused beyond
    ranges.MAX_STEPS (check_steps)."""
    if args.steps is not None:
        if args.duration is not None:
            raise CommandLineError("--duration and --steps both set the run's length; give one")
        steps = utils.check_whole("steps", args.steps, 1)
        return check_steps("steps", f"{steps:.9g}", steps, scene.h)
    if args.duration is not None:
        duration = args.duration
    duration, h = utils.check_positive("duration", duration), scene.h
    if duration < h:
        raise utils.ParameterError("duration", f"duration {duration:g} s is shorter than one time "
                                   f"step h = {h:g} s")
    return check_steps("duration", f"{duration:g} s", duration / h, h)


def check_steps(name, value, steps, h):
    """`steps` of h (inf where duration / h overflowed) rounded to a whole number, or a
    ParameterError naming --steps or --duration (`name`, given as `value`) beyond MAX_STEPS."""
    if not steps <= ranges.MAX_STEPS:
        raise utils.ParameterError(name, f"{name} = {value}: {steps:.9g} steps of h = {h:g} s "
                                   f"(at most {ranges.MAX_STEPS:.0e})")
    return int(round(steps))


def unfinished(scene, steps):
    """The scene with a warning where a tablecloth run ends before its closed-form dish stops."""
    if scene.surface is None:
        return scene
    s, end = scene.surface, steps * scene.h
    stop = tablecloth.stop_time(s.pull_speed, s.pull_length, scene.mu, s.t_pull,
                                             -scene.g[1])
    if end >= stop:
        return scene
    said = (f"the run ends at {end:.3g} s, before the dish stops ({stop:.3g} s in the closed "
            f"form): its travel is unfinished")
    return dataclasses.replace(scene, warnings=scene.warnings + (said,))


def frame_stride(args, scenes):
    """--frame-stride, or the largest giving FRAMES_PER_SECOND a simulated second at the least h."""
    if args.frame_stride is not None:
        return utils.check_whole("frame-stride", args.frame_stride, 1)
    return max(1, math.floor(1.0 / (FRAMES_PER_SECOND * min(s.h for s in scenes)) + 1e-9))


def plan_from_args(runs):
    """The run.Plan the command line's runs ask for (ValueError or CommandLineError if bad)."""
    args = runs[0]
    for flag in ("--size", "--speed"):
        if getattr(args, flag[2:]) is not None and not args.window:
            raise CommandLineError(f"{flag} applies only to the window: add --window or drop it")
    if args.window and len(runs) > 1:
        name = args.label.split(" = ")[0]
        raise CommandLineError(f"--window shows one run; compare the {len(runs)} --{name} runs "
                               f"without it")
    scenes = [scene_from_args(a) for a in runs]
    labels = [a.label or LABEL[a.scene].format(how="dragged" if a.drag else "pushed", **s.params)
              for a, s in zip(runs, scenes)]
    asked = all(a.steps is not None or a.duration is not None for a in runs)
    duration = None if asked else default_duration(scenes, runs[0].scene)
    steps = [steps_from_args(a, s, duration) for a, s in zip(runs, scenes)]
    scenes = [unfinished(scene, n) for scene, n in zip(scenes, steps)]
    return run.Plan(scenes=scenes, labels=labels, tags=[a.tag for a in runs], steps=steps,
                    out=args.out, stride=frame_stride(args, scenes), frames=not args.no_frames,
                    forces=not args.no_forces, said=args.said, kind=args.scene)


def refusal(err):
    """The line that refuses a command line: 'simulator.py: error: --flag: ...' (flag_of)."""
    return f"simulator.py: error: {flag_of(err)}{err}"


def flag_of(err):
    """'--flag: ' for the parameter a ValueError names (utils.ParameterError), or ''."""
    flag = FLAG_OF.get(getattr(err, "parameter", None))
    return f"{flag}: " if flag else ""
