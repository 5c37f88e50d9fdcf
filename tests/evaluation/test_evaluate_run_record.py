"""``evaluate`` reads a run record: a dataset whose ``source`` is a run.mcap (its kept pairs) scores the
same as the folder it was recorded from."""

from __future__ import annotations

import json
import shutil

from dip3d_vehicle.cli import main
from dip3d_vehicle.dataset import load_dataset
from dip3d_vehicle.record.mcap_log import McapRunWriter


def test_evaluate_on_a_run_record_matches_the_folder(sim_dataset, tmp_path, capsys):
    ds = load_dataset(sim_dataset)
    with McapRunWriter(tmp_path / "run.mcap", None, {"command": "test"}, image_format="png",
                       keep_images_every=1) as record:
        for ann, frame in ds.pairs():
            record.images(ann.index, frame.left, frame.right)
    annotations = json.loads((sim_dataset / "annotations.json").read_text())
    order = {a.index: i for i, (a, _) in enumerate(ds.pairs())}
    for frame in annotations["frames"]:  # in a source, "index" is the position of the pair
        frame["index"] = order[frame["index"]]
    annotations["source"] = "record:run.mcap"
    (tmp_path / "annotations.json").write_text(json.dumps(annotations))
    shutil.copy(sim_dataset / "calib.yaml", tmp_path / "calib.yaml")
    reports = []
    for root in (sim_dataset, tmp_path):
        assert main(["evaluate", str(root), "--json", "--profile", "default", "--no-progress"]) == 0
        reports.append(json.loads(capsys.readouterr().out)["profiles"]["default"])
    folder, record_report = reports
    assert record_report["table"] == folder["table"]
    strip = [[{k: v for k, v in f.items() if k != "index"} for f in r["frames"]] for r in reports]  # positions
    assert strip[0] == strip[1] and len(strip[0]) == 4  # status, chosen, correct, selected_px, error_px
    assert record_report["summary"] == folder["summary"]
