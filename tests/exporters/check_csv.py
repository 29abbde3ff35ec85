"""Reads a CSV file with Python's csv module (RFC 4180 dialect: commas,
double quotes, CRLF line ends), checks that every record ends with CRLF and
has the header's number of fields, and prints {"header": [...], "rows":
[[...], ...]} as JSON; exits 1 with one line naming the problem otherwise.

    python3 check_csv.py FILE.csv
"""
import csv
import json
import sys


def main():
    with open(sys.argv[1], "rb") as raw:
        data = raw.read()
    if data and not data.endswith(b"\r\n"):
        print("check_csv: the file does not end with CRLF")
        sys.exit(1)
    with open(sys.argv[1], newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f, dialect="excel", strict=True))
    if not rows:
        print("check_csv: no header row")
        sys.exit(1)
    header = rows[0]
    for number, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            print(f"check_csv: record {number} has {len(row)} fields, the header {len(header)}")
            sys.exit(1)
    print(json.dumps({"header": header, "rows": rows[1:]}))


main()
