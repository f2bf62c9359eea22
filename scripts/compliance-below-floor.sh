#!/usr/bin/env bash
# What a compliant pusher costs below the contact part's floor: six simulated pushes of rect2 (the same plans, clocks
# and noise each time) with the simulator's compliant pusher at growing compliances, each set diagnosed with the
# standard catalogue. Prints, per compliance, the contact part's slope, its lag under the friction force against its
# floor, the verdict and the corrected model's held-out error beside that of the same pushes without the compliance.
# A second table does the same for the rod's own contact, with no compliant pusher: the simulator's contact stiffness
# at the ends and the middle of the range its clean validation trials draw (5-30 kN/m) and beyond it. Each set is also
# diagnosed with --measured-contact-compliance (the base model's rod giving way by the measured slope): its held-out
# error is the last two columns.
#
#   scripts/compliance-below-floor.sh [BUILD_DIR=build]
set -euo pipefail
build="${1:-build}"
bin="$build/pushpred"
if [ ! -x "$bin" ]; then
    echo "compliance-below-floor.sh: $bin is not there; build the pushpred target first" >&2
    exit 2
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# Side, contact position, push angle [rad], speed [m/s]: pushes from every side, some off the normal.
plans=("0 0.5 0.0 0.05" "1 0.3 0.2 0.02" "2 0.6 -0.2 0.08" "3 0.5 0.1 0.03" "0 0.7 -0.3 0.04" "1 0.5 0.0 0.1")
compliances=(0 0.00005 0.0001 0.0002 0.0004 0.0008)
stiffnesses=(30000 10000 5000 2500)

# push_set DIR CONFIG EFFECT: the six pushes with the scenario file CONFIG and the effect, diagnosed.
push_set() {
    local dir="$1" config="$2" effect="$3" i=0
    mkdir -p "$dir"
    for plan in "${plans[@]}"; do
        read -r side position angle speed <<<"$plan"
        "$bin" simulate --config "$config" --side "$side" --position "$position" --angle "$angle" --speed "$speed" \
            --seed $((6000 + i)) --effect "$effect" --out "$dir/p$i.h5" >/dev/null
        i=$((i + 1))
    done
    "$bin" diagnose "$dir"/p*.h5 --shape rect2 --no-plots --out "$dir/diagnosis" >/dev/null
    "$bin" diagnose "$dir"/p*.h5 --shape rect2 --no-plots --measured-contact-compliance \
        --out "$dir/diagnosis-measured" >/dev/null
}

"$bin" simulate --shape rect2 --print-config >"$work/rect2.json"
for c in "${compliances[@]}"; do push_set "$work/c$c" "$work/rect2.json" "compliant_pusher=$c"; done
for k in "${stiffnesses[@]}"; do
    python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); d["contact_stiffness_N_m"] = float(sys.argv[2]);
json.dump(d, open(sys.argv[3], "w"))' "$work/rect2.json" "$k" "$work/k$k.json"
    push_set "$work/k$k" "$work/k$k.json" "compliant_pusher=0"
done

python3 - "$work" "${compliances[@]}" -- "${stiffnesses[@]}" <<'EOF'
import json, sys
work = sys.argv[1]
split = sys.argv.index("--")
compliances, stiffnesses = sys.argv[2:split], sys.argv[split + 1:]


def read(folder):
    d = json.load(open(f"{work}/{folder}/diagnosis/diagnosis.json"))
    m = json.load(open(f"{work}/{folder}/diagnosis-measured/diagnosis.json"))["error_after"]
    a = d["adequacy"]
    verdict = "unexplained" if a["verdict"].startswith("unexplained") else a["verdict"]
    found = ", ".join(d["found"]) if d["found"] else "nothing"
    return (a["contact"], verdict, found, d["error_after"]["pos_mm_mean"], d["error_after"]["theta_deg_mean"],
            m["pos_mm_mean"], m["theta_deg_mean"])


def table(first_column, rows, reference):
    print(f"| {first_column} | contact slope [mm/N] | lag [mm] | floor [mm] | verdict | found | held-out error "
          "[mm / deg] | against the reference | with the measured compliance | against its reference |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    ref_pos, ref_yaw, mref_pos, mref_yaw = reference
    for label, (contact, verdict, found, pos, yaw, mpos, myaw) in rows:
        print(f"| {label} | {1e3 * contact['compliance_m_N']:.3f} +- {1e3 * contact['compliance_m_N_std']:.3f} | "
              f"{contact['lag_mm']:.2f} | {contact['floor_mm']:.2f} | {verdict} | {found} | {pos:.2f} / {yaw:.2f} | "
              f"{pos / ref_pos:.2f} / {yaw / ref_yaw:.2f} | {mpos:.2f} / {myaw:.2f} | "
              f"{mpos / mref_pos:.2f} / {myaw / mref_yaw:.2f} |")


pusher = [(f"{1e3 * float(c):.2f}", read(f"c{c}")) for c in compliances]
print("A compliant pusher (contact stiffness 10 kN/m); the reference is the same pushes without it.")
print()
table("pusher compliance [mm/N]", pusher, pusher[0][1][3:])
print()
contact = [(f"{float(k) / 1e3:g} ({1e3 / float(k):.2f} mm/N)", read(f"k{k}")) for k in stiffnesses]
print("The rod's own contact, no compliant pusher; the reference is the stiffest contact.")
print()
table("contact stiffness [kN/m]", contact, contact[0][1][3:])
EOF
