"""The C = 100 red cell of record c100_s46 continued from its 1 ms checkpoint to 3 ms
(session 47), against the case's own run (C = 10) over the same time; the same measures
(../c100_s46/measure.py). Writes result.md here.

    /usr/bin/python3 verification/records/rbc_in_tube/c100_t3_s47/measure.py C100_RUN C10_RUN
"""
import importlib.util
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
spec = importlib.util.spec_from_file_location("c100_s46", HERE.parent / "c100_s46" / "measure.py")
c100_s46 = importlib.util.module_from_spec(spec)
spec.loader.exec_module(c100_s46)

if __name__ == "__main__":
    print(c100_s46.report(Path(sys.argv[1]), Path(sys.argv[2]), 3.0, HERE,
                          "A red cell with C = 100 in the 10 um tube, to 3 ms (session 47)"),
          end="")
