"""Checks a JUnit XML file against the structure of the JUnit schema that
Jenkins reads (junit-10.xsd of its xunit plugin: testsuites > testsuite >
properties, testcase > skipped, error, failure, system-out, system-err), and
that each testsuite's counts agree with its testcases. Prints the file's
content as JSON for the tests to compare with the report; exits 1 with one
line naming the problem otherwise.

    python3 check_junit.py FILE.xml
"""
import json
import re
import sys
import xml.etree.ElementTree as ET

# Element: (allowed attributes, required attributes, children in order as (name, min, max or None)).
SCHEMA = {
    "testsuites": ({"name", "time", "tests", "failures", "disabled", "errors"}, set(),
                   [("testsuite", 0, None)]),
    "testsuite": ({"name", "tests", "failures", "errors", "time", "disabled", "skipped", "timestamp",
                   "hostname", "id", "package"}, {"name", "tests"},
                  [("properties", 0, 1), ("testcase", 0, None), ("system-out", 0, 1), ("system-err", 0, 1)]),
    "properties": (set(), set(), [("property", 0, None)]),
    "property": ({"name", "value"}, {"name", "value"}, []),
    "testcase": ({"name", "assertions", "time", "classname", "status"}, {"name"},
                 [("skipped", 0, 1), ("error", 0, None), ("failure", 0, None), ("system-out", 0, None),
                  ("system-err", 0, None)]),
    "failure": ({"type", "message"}, set(), []),
    "error": ({"type", "message"}, set(), []),
    "skipped": ({"message"}, set(), []),
    "system-out": (set(), set(), []),
    "system-err": (set(), set(), []),
}
COUNTS = {"tests", "failures", "errors", "skipped", "disabled", "assertions"}
DECIMAL = re.compile(r"^-?[0-9]+(\.[0-9]+)?([eE][-+]?[0-9]+)?$")


def fail(message):
    print("check_junit: " + message)
    sys.exit(1)


def check(element, path):
    if element.tag not in SCHEMA:
        fail(f"{path}: element <{element.tag}> is not in the schema")
    allowed, required, children = SCHEMA[element.tag]
    for name, value in element.attrib.items():
        if name not in allowed:
            fail(f"{path}: <{element.tag}> has attribute '{name}', which the schema lacks")
        if name in COUNTS and not value.isdigit():
            fail(f"{path}: {name}=\"{value}\" is not a count")
        if name == "time" and not DECIMAL.match(value):
            fail(f"{path}: time=\"{value}\" is not a decimal")
    for name in required:
        if name not in element.attrib:
            fail(f"{path}: <{element.tag}> lacks the required attribute '{name}'")
    position = 0
    for child in element:
        while position < len(children) and children[position][0] != child.tag:
            position += 1
        if position == len(children):
            fail(f"{path}: <{child.tag}> is not allowed in <{element.tag}> here")
    for name, least, most in children:
        n = sum(1 for child in element if child.tag == name)
        if n < least or (most is not None and n > most):
            fail(f"{path}: <{element.tag}> has {n} <{name}>")
    if not children and len(element) > 0:
        fail(f"{path}: <{element.tag}> holds elements")
    for i, child in enumerate(element):
        check(child, f"{path}/{child.tag}[{i}]")


def main():
    root = ET.parse(sys.argv[1]).getroot()
    if root.tag != "testsuites":
        fail(f"the root is <{root.tag}>, not <testsuites>")
    check(root, "testsuites")
    suites = []
    for suite in root.findall("testsuite"):
        cases = []
        for case in suite.findall("testcase"):
            failure = case.find("failure")
            out = case.find("system-out")
            cases.append({
                "name": case.get("name"),
                "classname": case.get("classname"),
                "failure": None if failure is None else {
                    "message": failure.get("message"), "type": failure.get("type"), "text": failure.text or ""},
                "out": None if out is None else (out.text or ""),
            })
        counted = {"tests": len(cases), "failures": sum(1 for c in cases if c["failure"]),
                   "errors": len(suite.findall("testcase/error")), "skipped": len(suite.findall("testcase/skipped"))}
        for name, n in counted.items():
            if name in suite.attrib and int(suite.get(name)) != n:
                fail(f"testsuite {suite.get('name')}: {name}=\"{suite.get(name)}\" but it has {n}")
        properties = {p.get("name"): p.get("value") for p in suite.findall("properties/property")}
        suites.append({"name": suite.get("name"), "tests": int(suite.get("tests")),
                       "failures": int(suite.get("failures", "0")), "properties": properties, "cases": cases})
    for name in ("tests", "failures"):
        total = sum(s[name] for s in suites)
        if name in root.attrib and int(root.get(name)) != total:
            fail(f"testsuites: {name}=\"{root.get(name)}\" but its suites have {total}")
    print(json.dumps({"suites": suites, "tests": int(root.get("tests", "0")),
                      "failures": int(root.get("failures", "0"))}))


main()
