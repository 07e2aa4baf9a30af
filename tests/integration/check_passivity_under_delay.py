"""Checks passivity_under_delay.sh: no passivity violation left uncorrected
with the models 0-200 ms late, on three scenes."""
import re
import sys

from checks import check, finish, read_text

work = sys.argv[1]
scenes = {"t1": "tissue_block", "t2": "acupuncture", "t3": "cutting"}
print("delay_ms session scene models force_peak_N passivity_corrected bounded uncorrected model_age_p99_ms")
for delay in (0, 50, 100, 200):
    out = read_text(work, f"delay_{delay}.out")
    blocks = re.split(r"(?=bridge: device \S+, session )", out)[1:]
    check(len(blocks) == 3, f"{delay} ms: three devices reported")
    for block in blocks:
        session = re.search(r"session (\w+)", block).group(1)
        models = int(re.search(r"force models received (\d+)", block).group(1))
        peak = float(re.search(r"force peak ([\d.]+) N", block).group(1))
        corrected, bounded, uncorrected = map(
            int, re.search(r"passivity corrected (\d+) \(bounded (\d+), uncorrected (\d+)\)", block).groups())
        age = re.search(r"model age p50 [\d.]+ / p99 ([\d.]+)", block)
        print(f"{delay} {session} {scenes[session]} {models} {peak:.3f} {corrected} {bounded} {uncorrected} "
              f"{age.group(1) if age else '-'}")
        check(models > 1000, f"{delay} ms, {session}: models reached the device ({models})")
        check(uncorrected == 0, f"{delay} ms, {session}: no passivity violation left uncorrected ({uncorrected})")
        check(0.0 < peak <= 2.5, f"{delay} ms, {session}: the device was pressed, within the clamp ({peak:.3f} N)")
finish()
