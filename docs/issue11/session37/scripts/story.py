"""Print the mission story of a sitl run:  PYTHONPATH=. python story.py RUN_DIR/run.mcap"""
import sys
from dip3d_vehicle.record.mcap_log import McapRunReader
r=McapRunReader(sys.argv[1])
for m in r.messages(("/story",)):
    print(r.decode(m).message[:2500])
