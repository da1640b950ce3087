#!/usr/bin/python3
"""Every Python script of the project runs with Debian's /usr/bin/python3,
where scripts/setup.sh installs matplotlib and numpy, whatever python3 comes
first on PATH (a virtualenv's, a conda one without those modules).

Checks: each scripts/*.py and scripts/tests/*.py starts with
"#!/usr/bin/python3" and is executable; the README never tells the user to
run a script with a bare `python3`; and report.py, run by its shebang with a
python3 that always fails first on PATH, still works.
"""

import glob
import os
import re
import stat
import subprocess
import tempfile
import unittest

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
SHEBANG = "#!/usr/bin/python3"


def python_scripts():
    return sorted(glob.glob(os.path.join(ROOT, "scripts", "*.py")) +
                  glob.glob(os.path.join(ROOT, "scripts", "tests", "*.py")))


class Shebangs(unittest.TestCase):
    def test_there_are_scripts(self):
        names = [os.path.basename(p) for p in python_scripts()]
        self.assertIn("report.py", names)
        self.assertGreaterEqual(len(names), 8)

    def test_every_script_names_debians_python(self):
        for path in python_scripts():
            with self.subTest(script=os.path.relpath(path, ROOT)):
                with open(path, encoding="utf-8") as f:
                    self.assertEqual(f.readline().rstrip("\n"), SHEBANG)
                self.assertTrue(os.stat(path).st_mode & stat.S_IXUSR, "not executable")

    def test_readme_runs_no_script_with_a_bare_python3(self):
        with open(os.path.join(ROOT, "README.md"), encoding="utf-8") as f:
            for number, line in enumerate(f, 1):
                bare = re.search(r"(?<![/\w])python3 +\S*scripts/\S+\.py", line)
                self.assertIsNone(bare, "README.md:%d: %s" % (number, line.strip()))

    def test_report_runs_with_another_python3_first_on_path(self):
        with tempfile.TemporaryDirectory() as tmp:
            fake = os.path.join(tmp, "python3")
            with open(fake, "w") as f:
                f.write("#!/bin/sh\necho 'not Debian python3' >&2\nexit 97\n")
            os.chmod(fake, 0o755)
            env = dict(os.environ, PATH=tmp + os.pathsep + os.environ.get("PATH", ""))
            r = subprocess.run([os.path.join(ROOT, "scripts", "report.py"), "--help"],
                               capture_output=True, text=True, env=env, timeout=120)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("usage", r.stdout)


if __name__ == "__main__":
    unittest.main()
