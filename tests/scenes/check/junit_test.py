"""check --junit read back by a real JUnit reader (Debian's python3-junitparser).

Goldens for two scenes (copies of shipped ones) are made in a scratch folder;
one copy's shot is then made faster, so that a check of both has one pass and
one failure. The
XML must name both scenes, carry the failure's verdict line and the paths of
its evidence (files that exist), and a folder given as --junit is refused
before any scene runs (exit 2), nothing written.
Usage: junit_test.py PLAUSIBLE
"""
import os
import shutil
import subprocess
import sys
import tempfile

from junitparser import Error, Failure, JUnitXml


def check(exe, args, cwd):
    return subprocess.run([exe, "check", *args], cwd=cwd, capture_output=True, text=True)


def main():
    exe = os.path.abspath(sys.argv[1])
    work = tempfile.mkdtemp(prefix="plausible-junit-")
    try:
        scenes = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "scenes")
        for name in ("orbit", "ballistic"):
            shutil.copyfile(os.path.join(scenes, name + ".toml"), os.path.join(work, name + ".toml"))
        files = ["orbit.toml", "ballistic.toml"]
        made = check(exe, [*files, "--golden", "golden", "--update", "all", "--report", "made"], work)
        assert made.returncode == 0, made.stdout + made.stderr
        path = os.path.join(work, "ballistic.toml")
        with open(path) as f:
            text = f.read()
        with open(path, "w") as f:
            f.write(text.replace("velocity = [8.660254037844387, 5.0, 0]", "velocity = [9.5, 5.0, 0]", 1))

        run = check(exe, [*files, "--golden", "golden", "--report", "out", "--junit", "j.xml"], work)
        assert run.returncode == 1, "one scene fails: exit 1\n" + run.stdout + run.stderr
        xml = JUnitXml.fromfile(os.path.join(work, "j.xml"))
        cases = {case.name: case for suite in xml for case in suite}
        assert set(cases) == {"orbit", "ballistic"}, cases
        assert xml.tests == 2 and xml.failures == 1 and xml.errors == 0, (xml.tests, xml.failures, xml.errors)
        assert cases["orbit"].is_passed, cases["orbit"].result
        [failure] = cases["ballistic"].result
        assert isinstance(failure, Failure) and failure.type == "fail", failure
        verdict = [line for line in run.stdout.splitlines() if line.startswith("ballistic ")][0]
        assert failure.message in verdict, (failure.message, verdict)
        evidence = [line.split(": ", 1)[1] for line in failure.text.splitlines()[1:] if ": " in line]
        assert any(path.endswith("side.png") for path in evidence), failure.text
        for path in evidence:
            assert os.path.isfile(os.path.join(work, path)), "evidence on disk: " + path

        os.mkdir(os.path.join(work, "a-folder"))
        refused = check(exe, ["orbit.toml", "--golden", "golden", "--report", "out2", "--junit", "a-folder"], work)
        assert refused.returncode == 2, refused.stdout + refused.stderr
        assert "a-folder" in refused.stderr, refused.stderr
        assert not os.path.exists(os.path.join(work, "out2")), "refused before any scene ran"
        assert not any(isinstance(r, Error) for c in cases.values() for r in c.result)
    finally:
        shutil.rmtree(work)
    print("check --junit: 2 testcases, 1 failure with its verdict and evidence; a folder refused")


if __name__ == "__main__":
    main()
