"""Measured data for ``rvcoax discrepancy``: every refusal names the file, the line and column, and the reason.

The data are validated before anything is solved (the stations' 0 … L check needs only the base
model), so each case here takes well under a second.
"""

from __future__ import annotations

from hostile import Hostile
from hostile._files import LONG_CELL, write

K = "measured"
TABLE = "T1_input_Nm,T2_output_Nm,Y_input_mm,Y_output_mm\n"
PATHS = "T1_input_Nm,T2_output_Nm,shaft,x_mm,uy_mm\n"
GOOD_TABLE_ROW = "1.43,200,0.0000603,0.0042594\n"
GOOD_PATHS_ROW = "1.43,200,output,10,-0.001\n"


def _measured(text: str, newline: str | None = ""):
    def argv(folder):
        return ["discrepancy", "--measured", write(folder, "measured.csv", text, newline), "--out", str(folder / "out")]

    return argv


def _case(label: str, text: str, *expected: str, newline: str | None = "") -> Hostile:
    return Hostile(f"{K}: {label}", K, _measured(text, newline), ("measured data", "measured.csv") + expected)


CASES: list[Hostile] = []

# number syntax in every kind of column (plain_number, as for load cases)
for cell, words in (("1_00", "'_' digit separators"), ("٧٠", "not ASCII"), ("７０", "not ASCII"),
                    ("0x1A", "'0x1A' is not a number"), ("1e999", "beyond the range"), ("nan", "not a finite number"),
                    ("inf", "not a finite number"), ("1,5", "values but 4 columns"), ("12 mm", "'12 mm' is not a number")):
    CASES.append(_case(f"table Y_output_mm {cell!r}", TABLE + GOOD_TABLE_ROW + f"1,140,0.00005,{cell}\n",
                       "line 3", words))
CASES.append(_case("table T1 '٧٠'", TABLE + "٧٠,140,0.00005,0.004\n", "line 2, column T1_input_Nm", "not ASCII"))
CASES.append(_case("table T2 '２００'", TABLE + "1,２００,0.00005,0.004\n", "line 2, column T2_output_Nm", "not ASCII"))
CASES.append(_case("paths x_mm '1_0'", PATHS + "1,140,output,1_0,0.001\n", "line 2, column x_mm", "'_' digit separators"))
CASES.append(_case("paths uy_mm '-٠.١'", PATHS + "1,140,input,10,-٠.١\n", "line 2, column uy_mm", "not ASCII"))
CASES.append(_case("paths sigma_mm '1e-5_0'", PATHS.replace("uy_mm", "uy_mm,sigma_mm") + "1,140,input,10,0.001,1e-5_0\n",
                   "line 2, column sigma_mm", "'_' digit separators"))

# consistency with sweep --cases: the same torque bound
CASES.append(_case("table T1 1e12 N·m", TABLE + "1e12,140,0.00005,0.004\n", "line 2, column T1_input_Nm",
                   "beyond any plausible rig torque"))
CASES.append(_case("paths T2 -2e6 N·m", PATHS + "1,-2e6,input,10,0.001\n", "line 2, column T2_output_Nm",
                   "beyond any plausible rig torque"))
# x outside the measured path, with the line
CASES.append(_case("paths x_mm beyond L", PATHS + GOOD_PATHS_ROW + "1.43,200,output,100,-0.001\n1,140,input,5000,0.001\n",
                   "line 4, column x_mm", "outside its measured path"))
CASES.append(_case("paths x_mm negative", PATHS + "1,140,input,-5,0.001\n1,140,input,10,0.001\n",
                   "line 2, column x_mm", "outside its measured path"))

# parser limits: a field over the csv module's limit, a quote left open, CR-only line ends counted as lines
CASES.append(_case("field over 131072 characters", TABLE + GOOD_TABLE_ROW + f"1,140,\"{LONG_CELL}\",0.004\n",
                   "line 3", "cannot be read as CSV"))
CASES.append(_case("quote left open", TABLE + GOOD_TABLE_ROW + "1,140,\"0.00005,0.004\n", "line 3",
                   "is a quote left open"))
CASES.append(_case("CR-only line ends, bad cell on line 3", (TABLE + GOOD_TABLE_ROW + "1,140,abc,0.004\n")
                   .replace("\n", "\r"), "line 3, column Y_input_mm", "'abc' is not a number"))
CASES.append(_case("CRLF line ends, bad cell on line 3", (TABLE + GOOD_TABLE_ROW + "1,140,0.00005,1_0\n")
                   .replace("\n", "\r\n"), "line 3, column Y_output_mm", "'_' digit separators"))

# schema and table rules
CASES.append(_case("semicolon header", TABLE.replace(",", ";") + "1;140;0.00005;0.004\n", "line 1",
                   "separated by semicolons"))
CASES.append(_case("repeated column", TABLE.replace("\n", ",Y_input_mm\n") + "1,140,0.00005,0.004,0.1\n", "line 1",
                   "appear more than once"))
CASES.append(_case("unknown column", TABLE.replace("\n", ",temperature_C\n") + "1,140,0.00005,0.004,20\n", "line 1",
                   "unknown column(s) temperature_C"))
CASES.append(_case("negative magnitude", TABLE + "1,140,-0.00005,0.004\n", "line 2, column Y_input_mm", "magnitudes"))
CASES.append(_case("duplicated case", TABLE + GOOD_TABLE_ROW + GOOD_TABLE_ROW, "line 3", "duplicated load case"))
CASES.append(_case("Y in µm", TABLE + "1,140,60.3,4259.4\n", "line 2, column Y_output_mm", "looks like µm"))
CASES.append(_case("shaft 'middle'", PATHS + "1,140,middle,10,0.001\n", "line 2, column shaft", "not input or output"))
CASES.append(_case("sigma 0", PATHS.replace("uy_mm", "uy_mm,sigma_mm") + "1,140,input,10,0.001,0\n",
                   "line 2, column sigma_mm", "must be > 0"))
CASES.append(_case("missing cell", TABLE + "1,140,0.00005\n", "line 2, column Y_output_mm", "value is missing"))
CASES.append(_case("header only", TABLE, "no data rows under the header"))
CASES.append(_case("second value at a station", PATHS + GOOD_PATHS_ROW + GOOD_PATHS_ROW, "line 3",
                   "a second value for the output shaft"))
CASES.append(_case("x in metres", PATHS + "1,140,output,0.01,0.001\n1,140,output,0.15,0.002\n", "lines 2–3, column x_mm",
                   "looks like metres"))

# size: refused with the estimate and a suggestion before anything is solved (100,000 cases × the library: more
# than the 6 h one command may take, whatever the memory; issue 14 made a case-candidate 6 ms, so 30,000 no longer are)
CASES.append(_case("100,000 load cases", TABLE + "".join(f"{1 + i * 1e-3:.4f},{140 + i * 0.1:.2f},0.00005,0.004\n"
                                                         for i in range(100_000)),
                   "200,000 observations in 100,000 load cases × 57 candidate effects", "would take",
                   "thin the stations"))
