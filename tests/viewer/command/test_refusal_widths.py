"""Every refusal of every scene flag in every scene is one line of at most 100 columns naming the
flag (issue 40): each flag given values at float64's edges, read as the command line reads it
(cli.parse_command_line, cli.plan_from_args: nothing is written), its line as main prints it
(cli.refusal), no RuntimeWarning on the way. The value the user gave may run longer, as a path
may (helpers.command.without_given)."""
import warnings

import pytest

from helpers.command import refused, without_given
from scenes import UNITS
from viewer.command import cli

WIDTH = 100
SCENES = ("square", "chalk", "tablecloth", *UNITS)
NUMBERS = ("nan", "inf", "-inf", "-1", "0", "1", "1e308", "1e-300", "1e-320", "1,nan", "1e30")
PAIRS = ("nan,1", "1,inf", "0,0", "1e308,1e308", "1e-320,1e-320", "-1e308,1", "1e-300,-1e-300",
         "0,-1e308", "0,-1e-320", "1,nan;1,2")
RUN_FLAGS = [(("--duration",), "duration", "SECONDS"), (("--steps",), "steps", "N"),
             (("--frame-stride",), "frame_stride", "N"), (("--slope-angle",), "slope_angle", "D")]
FLAGS = [(flags[0], metavar) for flags, _, metavar, *_ in cli.FLAGS + RUN_FLAGS
         if metavar != "START"]


def refusal(argv):
    """The line main prints for argv, or None where the command line is taken."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            cli.plan_from_args(cli.parse_command_line(argv))
        except (cli.CommandLineError, ValueError) as err:
            return cli.refusal(err)
    return None


@pytest.mark.parametrize("scene", SCENES)
def test_every_refusal_of_every_flag_fits_in_one_line(scene):
    lines = []
    for flag, metavar in FLAGS:
        for value in PAIRS if "," in metavar else NUMBERS:
            length = [] if flag in ("--duration", "--steps") else ["--steps", "3"]
            line = refusal(["--scene", scene, flag, value, *length])
            if line is not None:        # the flag, or the one to give instead (--center)
                assert line.startswith("simulator.py: error: ") and " --" in line, line
                lines.append((line, value))
    assert len(lines) > 5 * len(FLAGS)
    assert [line for line, value in lines      # the value as given and as printed aside
            if len(without_given(line, [value])) > WIDTH or "\n" in line] == []


def test_an_out_folder_that_is_not_empty_is_said_in_a_line_that_fits(tmp_path):
    """Its words fit in 100 columns beside the folder's own name (a path may run longer)."""
    line = refused(["--steps", "3"], tmp_path)
    assert line.startswith(f"simulator.py: error: --out: out folder {str(tmp_path)!r} is not empty")
    assert len(line.replace(repr(str(tmp_path)), "")) <= WIDTH, line
