"""For the report scripts run by hand (column_report.py, slope_runout_report.py): on a fresh
machine Debian's python3-h5py and python3-matplotlib are not there yet, so the script runs
scripts/setup.sh (which installs them and builds talus) and starts again under Debian's
/usr/bin/python3, where those packages live."""

import os
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
_RESTARTED = "TALUS_REPORT_SETUP_DONE"


def ensure_packages():
    try:
        import h5py  # noqa: F401
        import matplotlib  # noqa: F401
    except ImportError as missing:
        if os.environ.get(_RESTARTED):
            sys.exit(f"{missing} even after scripts/setup.sh; run the script with "
                     "/usr/bin/python3 (Debian's python3-h5py and python3-matplotlib)")
        subprocess.run([os.path.join(REPO, "scripts", "setup.sh")], check=True)
        os.environ[_RESTARTED] = "1"
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
