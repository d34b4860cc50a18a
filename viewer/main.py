"""`python simulator.py [flags]`: the command line read (command.cli), then the run to files
(command.run) or in the window (demo.window, loaded only for --window); returns the exit code."""
import sys

from viewer.command import cli, run


def main(argv):
    """Run the command line; returns the exit code (messages on stderr)."""
    with run.Signals() as signals:
        try:
            try:
                runs = cli.parse_command_line(argv)
                plan = cli.plan_from_args(runs)
                if runs[0].window:
                    from viewer.demo import window
                    return window.run_window(plan, runs[0].speed, runs[0].size, signals)
                return run.to_files(plan, signals)
            except (cli.CommandLineError, ValueError) as err:
                signals.close()         # the error is said: a signal from here on only waits
                print(cli.refusal(err), file=sys.stderr)
                return 2
        except run.Stopped as stopped:      # before the run, or as its error was found
            signals.close()
            print(f"simulator.py: stopped: {stopped.reason}; nothing written", file=sys.stderr)
            return stopped.code
