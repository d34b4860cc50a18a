"""The command line, `python simulator.py [flags]`: its flags, comparisons by lists, and its errors.

Every scene flag sets one of simulator.DEFAULTS (SCENE_FLAGS), or with `--scene chalk` one of
simulator.CHALK (CHALK_FLAGS and the SCENE_FLAGS the chalk has, CHALK_SHARED), and only the flags
given reach `simulator.build_scene` (`build_chalk_scene`). Any one scalar scene flag may take a comma-separated list (`--mu 0.1,0.11,0.2`)
and a pair flag a ';'-separated list of pairs (`--v0 "1,0;-2,0"`): one run per value, compared side by
side. A bad command line is one line on stderr naming the flag, and exit code 2, before anything is
written; the run itself (viewer/command/run.py, viewer/demo/window.py) ends in one line too.
"""
import argparse
import math
import re

import simulator
import utils
from viewer.command import run

DURATION = 6.0      # s, a run's and a comparison's: long enough to see mu = 0.11 come to rest (about 5.5 s)
CHALK_DURATION = 3.0    # s, the chalk's: about 17 stick-slip cycles of the pushed chalk
FRAMES_PER_SECOND = 30      # at least this many frames per simulated second by default

# (flags, scene parameter, what it is, metavar): every flag that sets a scene parameter
SCENE_FLAGS = [
    (("--mu",), "mu", "friction coefficient, no unit", "MU"),
    (("--h", "--dt"), "h", "time step in s", "SECONDS"),
    (("--n-seg",), "n_seg", "segments per side of the square", "N"),
    (("--side",), "side_len", "side length of the square in m", "METRES"),
    (("--k",), "k", "spring stiffness in N/m", "N_PER_M"),
    (("--density",), "rho", "density in kg/m^2", "KG_PER_M2"),
    (("--mass",), "mass", "total mass in kg, instead of --density", "KG"),
    (("--slope-normal",), "slope", "the slope's normal, normalized for you", "NX,NY"),
    (("--slope-point",), "slope_point", "a point on the slope in m", "OX,OY"),
    (("--center",), "center", "initial centre of the square in m", "X,Y"),
    (("--v0",), "v0", "initial velocity in m/s", "VX,VY"),
    (("--gravity",), "gravity", "gravity in m/s^2", "GX,GY"),
    (("--dhat",), "dhat", "barrier activation distance in m", "METRES"),
    (("--kappa",), "kappa", "barrier stiffness in N/m (P_b = sum of w dhat b(d), in J)", "KAPPA"),
    (("--epsv",), "epsv", "friction's eps_v in m/s", "M_PER_S"),
    (("--tol",), "tol", "Newton tolerance on ||p||_inf / h in m/s", "M_PER_S"),
    (("--friction-iterations",), "friction_updates",
     "fixed-point friction updates per step, fully implicit friction (Algorithm 5); 0: lagged", "N"),
    (("--max-newton",), "max_newton_iterations", "Newton iteration cap per solve", "N"),
    (("--newton-start",), "newton_start", "where each step's Newton starts: x_n, as the lecture, or x_tilde = "
     "x^n + h v^n cut back by CCD (the chalk's default)", "START"),
]
CHOICES = {"newton_start": utils.NEWTON_STARTS}      # the flags that take a word, not a number
# the chalk's own flags (each sets one of simulator.CHALK; --drag below), and the SCENE_FLAGS it has too
CHALK_FLAGS = [
    (("--tilt",), "tilt", "--scene chalk: the chalk's angle from the board in degrees", "DEG"),
    (("--grip",), "k_hand", "--scene chalk: the grip, each held node's spring stiffness in N/m", "N_PER_M"),
    (("--mu-static",), "mu_s", "--scene chalk: static friction coefficient (equal to --mu: one coefficient)", "MU"),
]
CHALK_SHARED = ("mu", "h", "k", "rho", "gravity", "dhat", "kappa", "epsv", "tol", "friction_updates",
                "max_newton_iterations", "newton_start")
WINDOW_FLAGS = ("--size", "--speed")
# the parameter a ValueError is about (utils.ParameterError.parameter) -> its flag
FLAG_OF = {**{param: flags[0] for flags, param, _, _ in SCENE_FLAGS + CHALK_FLAGS}, "slope_angle": "--slope-angle",
           "steps": "--steps", "duration": "--duration", "frame-stride": "--frame-stride", "out": "--out",
           "size": "--size", "speed": "--speed"}


class CommandLineError(Exception):
    """A bad command line: reported in one line, exit code 2."""


class Parser(argparse.ArgumentParser):
    def error(self, message):
        raise CommandLineError(message)


def pair(text):
    """'X,Y' as two floats."""
    try:
        values = [float(s) for s in text.replace(",", " ").split()]
    except ValueError:
        values = []
    if len(values) != 2:
        raise argparse.ArgumentTypeError(f"expected two numbers 'X,Y', got {text!r}")
    return tuple(values)


def whole(text):
    """A count flag's value (N): a number, checked to be whole where the scene or run is built."""
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"invalid int value: {text!r}") from None


def as_number(text, pair_flag):
    """A list value as the number (or pair) its flag parses it to, so '0.1' and '0.10' compare equal; the
    text itself where it does not parse (argparse then names it)."""
    try:
        return pair(text) if pair_flag else float(text)
    except (ValueError, argparse.ArgumentTypeError):
        return text


def is_pair(metavar):
    return "," in metavar


def make_parser():
    d = simulator.DEFAULTS
    ap = Parser(prog="simulator.py", allow_abbrev=False, description=(
        "Simulate the lecture's elastic square on a slope (implicit Euler as optimization, log-barrier "
        "contact, semi-implicit friction) and write into a folder: index.html, a page that plays the run; "
        "PNG frames and OBJ meshes; log.csv; plots.png and summary.png. Compare runs by giving one scene "
        "flag a list: comma-separated values, or ';'-separated pairs, e.g. --mu 0.1,0.11,0.2 (the lecture's "
        f"comparison; {DURATION:g} s unless --duration or --steps says otherwise)."))
    g = ap.add_argument_group("scene (the lecture's numbers by default)")
    g.add_argument("--scene", choices=("square", "chalk"), default="square",
                   help="square: the lecture's square on a slope (default); chalk: Rabinowicz's chalk pushed "
                        f"across a board, stick-slip ({CHALK_DURATION:g} s unless --duration or --steps says otherwise)")
    for flags, param, what, metavar in SCENE_FLAGS + CHALK_FLAGS:
        value = d[param] if param in d else simulator.CHALK[param]
        shown = (",".join(f"{v:g}" for v in value) if isinstance(value, tuple) else value if isinstance(value, str)
                 else f"{value:g}" if value is not None else "density x side^2")
        kind = ({"choices": CHOICES[param]} if param in CHOICES else
                {"type": pair if is_pair(metavar) else whole if metavar == "N" else float})
        g.add_argument(*flags, dest=param, metavar=metavar, default=argparse.SUPPRESS, help=f"{what} (default {shown})",
                       **kind)
    g.add_argument("--slope-angle", type=float, metavar="DEGREES",
                   help="slope angle in degrees, descending to the right, instead of --slope-normal")
    g.add_argument("--no-slope", action="store_true", help="free fall: no slope, no contact")
    g.add_argument("--drag", action="store_true", help="--scene chalk: drag the chalk (acute angle) instead of pushing it")
    r = ap.add_argument_group("run and output")
    r.add_argument("--duration", type=float, metavar="SECONDS",
                   help=f"simulated seconds (default {DURATION:g})")
    r.add_argument("--steps", type=whole, metavar="N", help="number of time steps, instead of --duration")
    r.add_argument("--out", metavar="FOLDER", help="a new or empty folder to write into (default: a new "
                   "one, output/<scene>-<date>-<time>; with --window, files only when given)")
    r.add_argument("--frame-stride", type=whole, metavar="N",
                   help=f"write a frame every N steps (default: {FRAMES_PER_SECOND} or more a simulated second)")
    r.add_argument("--no-forces", action="store_true", help="draw no force arrows in the frames")
    r.add_argument("--no-frames", action="store_true",
                   help="write only log.csv, plots.png and summary.png (no frames, OBJs or index.html)")
    r.add_argument("--window", action="store_true", help="show the run live in a pygame window (docs/live-demo.md)")
    r.add_argument("--size", type=float, metavar="PIXELS",
                   help="--window: its side in pixels (default: fit the display)")
    r.add_argument("--speed", type=float, metavar="FACTOR",
                   help="--window: simulated seconds per wall-clock second (default 1; 0.25: slow motion)")
    return ap


def attach_negative_values(argv):
    """['--k', '-2e4'] -> ['--k=-2e4']: argparse takes '-2e4', '-1,2' or '-inf' for an option, but no
    flag starts with a digit, a dot, 'inf' or 'nan', so such a token is always the previous option's value."""
    out = []
    for token in argv:
        if out and out[-1].startswith("--") and "=" not in out[-1] and re.match(r"^-([0-9.]|inf|nan)", token, re.I):
            out[-1] = f"{out[-1]}={token}"
        else:
            out.append(token)
    return out


def scene_flag_uses(argv):
    """(token index, flag, parameter, its value as typed, whether a pair flag) for each scene flag given."""
    kinds = {flag: (param, is_pair(metavar)) for flags, param, _, metavar in SCENE_FLAGS + CHALK_FLAGS for flag in flags}
    uses = []
    for i, token in enumerate(argv):
        flag, joined, value = token.partition("=")
        if flag in kinds and (joined or i + 1 < len(argv)):
            param, pair_flag = kinds[flag]
            uses.append((i, flag, param, value if joined else argv[i + 1], pair_flag))
    return uses


def parse_command_line(argv):
    """One argparse Namespace per run, each with its `label` and file `tag` ('' for a single run)."""
    argv = attach_negative_values(list(argv))
    parser = make_parser()
    uses = scene_flag_uses(argv)
    lists = [u for u in uses if (";" if u[4] else ",") in u[3]]
    if not lists:
        args = parser.parse_args(argv)
        args.label, args.tag, args.said = "", "", None
        return [args]
    if len(lists) > 1:
        raise CommandLineError(f"only one scene flag may take a list of values, got {lists[0][1]} and {lists[1][1]}")
    i, flag, param, text, pair_flag = lists[0]
    again = [u[1] for u in uses if u[2] == param and u[0] != i]
    if again:
        raise CommandLineError(f"{flag}: given a list ({text}) and again as {again[0]}; give it once")
    values = [v.replace(" ", "") for v in text.split(";" if pair_flag else ",")]
    if not all(values):
        raise CommandLineError(f"{flag}: the list {text!r} has an empty value")
    numbers = [as_number(value, pair_flag) for value in values]
    for j, number in enumerate(numbers):
        if number in numbers[:j]:
            raise CommandLineError(f"{flag}: the list {text} repeats a value: {values[numbers.index(number)]} "
                                   f"and {values[j]} are equal")
    runs, skip = [], i + (1 if "=" in argv[i] else 2)
    said = None if pair_flag else decimal_comma(flag, values)
    for value in values:
        args = parser.parse_args(argv[:i] + [f"{flag}={value}"] + argv[skip:])
        name = flag.lstrip("-")
        args.label, args.said = f"{name} = {value}", said
        args.tag = f"{name}_{value.replace(',', '_')}" if pair_flag else f"{name}{value}"
        runs.append(args)
    return runs


def decimal_comma(flag, values):
    """A list of two whole numbers given to a flag of decimals reads like a decimal comma ('--mu 0,11'):
    what it compares, said out loud as the run's first line; None for any other list."""
    counts = [flags[0] for flags, _, _, metavar in SCENE_FLAGS + CHALK_FLAGS if metavar == "N"]
    if flag in counts or len(values) != 2 or not all(re.fullmatch(r"-?[0-9]+", v) for v in values):
        return None
    name = flag.lstrip("-")
    return (f"comparing {name} = {values[0]} and {name} = {values[1]} (a list; a decimal is written "
            f"{values[0]}.{values[1]})")


def given_flags(args, table):
    """The first flag of each entry of `table` the command line gave, by parameter."""
    return {param: flags[0] for flags, param, _, _ in table if hasattr(args, param)}


def scene_from_args(args):
    """simulator.build_scene (build_chalk_scene with --scene chalk) with the scene flags given (the
    rest keep DEFAULTS, CHALK); a flag of the other scene is refused."""
    square_only = {p: f for p, f in given_flags(args, SCENE_FLAGS).items() if p not in CHALK_SHARED}
    square_only.update({"slope_angle": "--slope-angle"} if args.slope_angle is not None else {})
    square_only.update({"slope": "--no-slope"} if args.no_slope else {})
    chalk_only = list(given_flags(args, CHALK_FLAGS).values()) + ["--drag"] * args.drag
    if args.scene == "chalk":
        if square_only:
            raise CommandLineError(f"{next(iter(square_only.values()))} applies only to the square; "
                                   f"--scene chalk has no such parameter")
        overrides = {param: getattr(args, param) for _, param, _, _ in SCENE_FLAGS + CHALK_FLAGS
                     if hasattr(args, param)}
        return simulator.build_chalk_scene(drag=args.drag, **overrides)
    if chalk_only:
        raise CommandLineError(f"{chalk_only[0]} applies only to the chalk; add --scene chalk, or leave it out")
    overrides = {param: getattr(args, param) for _, param, _, _ in SCENE_FLAGS if hasattr(args, param)}
    slopes = (("--slope-normal", "slope" in overrides), ("--slope-angle", args.slope_angle is not None),
              ("--no-slope", args.no_slope))
    given = [flag for flag, on in slopes if on]
    if len(given) > 1:
        raise CommandLineError(f"{given[0]} and {given[1]} both set the slope; give one")
    if "rho" in overrides and "mass" in overrides:
        raise CommandLineError("--density and --mass both set the mass (it is density x side^2, or --mass); give one")
    if args.no_slope:
        overrides["slope"] = None
    elif args.slope_angle is not None:
        if not -90.0 < args.slope_angle < 90.0:
            raise utils.ParameterError("slope_angle", f"slope-angle must be in (-90, 90) degrees, got {args.slope_angle}")
        theta = math.radians(args.slope_angle)
        overrides["slope"] = (math.sin(theta), math.cos(theta))
    return simulator.build_scene(**overrides)


def steps_from_args(args, scene):
    """--steps, or --duration (default DURATION, the chalk's CHALK_DURATION) in steps of h."""
    if args.steps is not None:
        if args.duration is not None:
            raise CommandLineError("--duration and --steps both set the run's length; give one")
        return utils.check_whole("steps", args.steps, 1)
    duration = args.duration if args.duration is not None else CHALK_DURATION if scene.hand else DURATION
    duration = utils.check_positive("duration", duration)
    if duration < scene.h:
        raise utils.ParameterError("duration", f"duration {duration:g} s is shorter than one time step h = {scene.h:g} s")
    if not math.isfinite(duration / scene.h):
        raise utils.ParameterError("duration", f"duration {duration:g} s is more time steps of h = {scene.h:g} s than float64 "
                         f"can count (use --steps, or a larger h)")
    return int(round(duration / scene.h))


def frame_stride(args, scenes):
    """--frame-stride, or the largest stride giving FRAMES_PER_SECOND frames per simulated second at
    the smallest h (3 at h = 0.01: 33 frames per second)."""
    if args.frame_stride is not None:
        return utils.check_whole("frame-stride", args.frame_stride, 1)
    return max(1, math.floor(1.0 / (FRAMES_PER_SECOND * min(s.h for s in scenes)) + 1e-9))


def plan_from_args(runs):
    """The run.Plan the command line's runs ask for (ValueError or CommandLineError for a bad one)."""
    args = runs[0]
    for flag in WINDOW_FLAGS:
        if getattr(args, flag.lstrip("-")) is not None and not args.window:
            raise CommandLineError(f"{flag} applies only to the window; add --window, or leave {flag} out")
    if args.window and len(runs) > 1:
        raise CommandLineError(f"--window shows one run; --{runs[0].label.split(' = ')[0]} was given {len(runs)} "
                               f"values (compare them without --window)")
    scenes = [scene_from_args(a) for a in runs]
    return run.Plan(scenes=scenes, labels=[a.label or default_label(s) for a, s in zip(runs, scenes)],
                    tags=[a.tag for a in runs],
                    steps=[steps_from_args(a, s) for a, s in zip(runs, scenes)],
                    out=args.out, stride=frame_stride(args, scenes), frames=not args.no_frames, forces=not args.no_forces,
                    said=args.said)


def default_label(scene):
    """A single run's label: 'mu = 0.11'; the chalk's 'pushed, mu_s = 0.5, mu = 0.35'."""
    if scene.hand is None:
        return f"mu = {scene.mu:g}"
    return f"{'dragged' if scene.params['drag'] else 'pushed'}, mu_s = {scene.params['mu_s']:g}, mu = {scene.mu:g}"


def flag_of(err):
    """'--flag: ' for the flag of the parameter a ValueError is about (utils.ParameterError), or ''."""
    flag = FLAG_OF.get(getattr(err, "parameter", None))
    return f"{flag}: " if flag else ""
