"""`python -m railbrake` runs the CLI; shell completion completes commands and options; a reader of stdout that goes away (`railbrake ... | head`) ends
the command quietly, with the status a shell gives a command ended by SIGPIPE, and no message."""

import subprocess
import sys

from railbrake.cli._common import BROKEN_PIPE_STATUS


def test_python_dash_m_runs_the_command_line():
    done = subprocess.run([sys.executable, "-m", "railbrake", "--version"], capture_output=True, text=True)
    assert done.returncode == 0 and done.stdout.startswith("railbrake ")


def test_a_closed_pipe_on_stdout_ends_quietly():
    process = subprocess.Popen([sys.executable, "-m", "railbrake", "config", "show", "emergency-250-dry"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    process.stdout.close()              # the reader is gone before the first line is written
    stderr = process.stderr.read().decode()
    assert process.wait(timeout=60) == BROKEN_PIPE_STATUS
    assert stderr == ""


def test_shell_completion_completes_commands_and_options():
    """What bash's completion function (railbrake --show-completion bash) asks the CLI for."""
    import os
    import shutil
    command = shutil.which("railbrake", path=os.path.dirname(sys.executable))
    for words, cword, expected in (("railbrake ru", "1", "run"), ("railbrake run --no", "2", "--no-wsp")):
        env = dict(os.environ, _RAILBRAKE_COMPLETE="complete_bash", COMP_WORDS=words, COMP_CWORD=cword)
        done = subprocess.run([command], env=env, capture_output=True, text=True)
        assert done.returncode == 0 and expected in done.stdout.split(), done.stdout
