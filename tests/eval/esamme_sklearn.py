#!/usr/bin/env python3
"""E-SAMME against scikit-learn's SAMME on the data sets scikit-learn ships (issue 15, evaluation).

Writes each data set and its seeded 5 stratified folds to OUT/<name>/{X,y,folds}.csv, which both sides read; runs
AdaBoostClassifier(algorithm="SAMME") with stumps and with depth-3 trees on those folds, runs anchordb_eval_esamme
with stumps only (scikit-learn's weight update, weighted fits) and with the full base set, and prints the table.

  python3 tests/eval/esamme_sklearn.py --bin build/tests/anchordb_eval_esamme [--out /tmp/esamme_eval] [--rounds 50]
Needs Debian's python3-sklearn (scripts/setup installs it).
"""
import argparse
import json
import os
import subprocess
import time

import numpy as np
from sklearn.datasets import load_breast_cancer, load_digits, load_iris, load_wine
from sklearn.ensemble import AdaBoostClassifier
from sklearn.model_selection import StratifiedKFold
from sklearn.tree import DecisionTreeClassifier

DATASETS = {"iris": load_iris, "wine": load_wine, "breast_cancer": load_breast_cancer, "digits": load_digits}


def write_dataset(folder, x, y, folds):
    os.makedirs(folder, exist_ok=True)
    np.savetxt(os.path.join(folder, "X.csv"), x, delimiter=",", fmt="%.10g")
    np.savetxt(os.path.join(folder, "y.csv"), y, fmt="%d")
    np.savetxt(os.path.join(folder, "folds.csv"), folds, fmt="%d")


def sklearn_samme(x, y, folds, depth, rounds):
    correct = 0
    start = time.perf_counter()
    for f in range(folds.max() + 1):
        train, test = folds != f, folds == f
        model = AdaBoostClassifier(DecisionTreeClassifier(max_depth=depth), n_estimators=rounds, algorithm="SAMME",
                                   random_state=0)
        model.fit(x[train], y[train])
        correct += int((model.predict(x[test]) == y[test]).sum())
    return correct / len(y), time.perf_counter() - start


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--bin", required=True)
    parser.add_argument("--out", default="/tmp/esamme_eval")
    parser.add_argument("--rounds", type=int, default=50)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    rows = []
    for name, loader in DATASETS.items():
        x, y = loader(return_X_y=True)
        folds = np.zeros(len(y), dtype=int)
        for f, (_, test) in enumerate(StratifiedKFold(5, shuffle=True, random_state=args.seed).split(x, y)):
            folds[test] = f
        folder = os.path.join(args.out, name)
        write_dataset(folder, x, y, folds)
        row = {"data set": name, "n": len(y), "K": len(set(y))}
        for depth in (1, 3):
            acc, seconds = sklearn_samme(x, y, folds, depth, args.rounds)
            row[f"sklearn depth {depth}"] = (acc, seconds)
        for config in ("stumps", "full"):
            command = [args.bin, "--data", folder, "--config", config, "--rounds", str(args.rounds)]
            if config == "full":
                command += ["--update", "sklearn", "--selection", "weights", "--sample_factor", "0.6"]
            result = json.loads(subprocess.run(command, check=True, capture_output=True, text=True).stdout)
            row[f"E-SAMME {config}"] = (result["accuracy"], result["train_and_test_seconds"])
            row[f"kinds {config}"] = result["kinds"]
        rows.append(row)
        print(json.dumps(row), flush=True)
    print(f"\n5-fold stratified CV (StratifiedKFold shuffle, random_state={args.seed}), {args.rounds} rounds; "
          "accuracy (5-fold train+test seconds)")
    columns = ["sklearn depth 1", "sklearn depth 3", "E-SAMME stumps", "E-SAMME full"]
    print(f"{'data set':14s}" + "".join(f"{c:>24s}" for c in columns))
    for row in rows:
        print(f"{row['data set']:14s}" + "".join(f"{row[c][0]:>15.4f} ({row[c][1]:6.2f}s)" for c in columns))


if __name__ == "__main__":
    main()
