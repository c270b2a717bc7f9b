#!/usr/bin/env python3
"""Checks a Prometheus text exposition (a scraped /metrics page) with the Prometheus project's
own Python parser, then with rules the parser lets pass but a Prometheus server or promtool
would not: a family's HELP and TYPE once each and before its samples, a known type, counters
named *_total, histograms with a +Inf bucket equal to _count.

usage: check_metrics.py PAGE [FAMILY ...]
Every FAMILY named must be on the page. Prints one line per family; exits 1 naming the
first problem found."""
import sys

from prometheus_client.parser import text_string_to_metric_families


def fail(message):
    print("check_metrics: " + message, file=sys.stderr)
    sys.exit(1)


def check_comment_lines(text):
    """HELP then TYPE, once per family, before any of its samples; TYPE a known type."""
    helped, typed = set(), set()
    for number, line in enumerate(text.splitlines(), 1):
        if not line.startswith("#"):
            continue
        parts = line.split(None, 3)
        if len(parts) < 3 or parts[1] not in ("HELP", "TYPE"):
            continue
        name = parts[2]
        if parts[1] == "HELP":
            if name in helped:
                fail(f"line {number}: second HELP for {name}")
            if len(parts) < 4 or not parts[3].strip():
                fail(f"line {number}: empty HELP for {name}")
            helped.add(name)
        else:
            kind = parts[3] if len(parts) > 3 else ""
            if kind not in ("counter", "gauge", "histogram", "summary", "untyped"):
                fail(f"line {number}: TYPE of {name} is '{kind}', not a metric type")
            if name in typed:
                fail(f"line {number}: second TYPE for {name}")
            typed.add(name)
    if helped != typed:
        fail(f"families with HELP but no TYPE or the reverse: {sorted(helped ^ typed)}")
    return typed


def check_family(family):
    if family.type == "unknown" or family.type == "untyped":
        fail(f"{family.name}: samples without a TYPE line (untyped)")
    if family.type == "counter":
        # The parser strips _total from a counter's family name; the samples keep it.
        for sample in family.samples:
            if not sample.name.endswith(("_total", "_created")):
                fail(f"counter sample {sample.name} is not named *_total")
    if family.type == "histogram":
        series = {}
        for sample in family.samples:
            key = tuple(sorted((k, v) for k, v in sample.labels.items() if k != "le"))
            entry = series.setdefault(key, {"buckets": [], "count": None})
            if sample.name.endswith("_bucket"):
                entry["buckets"].append((float(sample.labels["le"]), sample.value))
            elif sample.name.endswith("_count"):
                entry["count"] = sample.value
        for key, entry in series.items():
            buckets = entry["buckets"]
            if not buckets or buckets[-1][0] != float("inf"):
                fail(f"{family.name}{dict(key)}: no +Inf bucket last")
            if buckets[-1][1] != entry["count"]:
                fail(f"{family.name}{dict(key)}: +Inf bucket {buckets[-1][1]} != _count {entry['count']}")
            counts = [count for _, count in buckets]
            if counts != sorted(counts):
                fail(f"{family.name}{dict(key)}: bucket counts are not cumulative")


def main():
    if len(sys.argv) < 2:
        fail("usage: check_metrics.py PAGE [FAMILY ...]")
    with open(sys.argv[1], encoding="utf-8") as f:
        text = f.read()
    typed = check_comment_lines(text)
    try:
        families = list(text_string_to_metric_families(text))
    except Exception as e:  # the parser's own refusal: the page is not valid
        fail(f"the Prometheus parser refused the page: {e!r}")
    seen = set()
    for family in families:
        if family.name in seen:
            fail(f"family {family.name} appears twice (its samples are not together)")
        seen.add(family.name)
        check_family(family)
        print(f"{family.name} {family.type} {len(family.samples)} samples")
    for wanted in sys.argv[2:]:
        if wanted not in typed:
            fail(f"family {wanted} is not on the page")
    print(f"check_metrics: {len(families)} families parsed")


if __name__ == "__main__":
    main()
