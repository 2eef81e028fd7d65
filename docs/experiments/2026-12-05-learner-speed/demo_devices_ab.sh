#!/bin/bash
# A/B of the demo's two training commands at 1 and 2 CPU devices (alternating), shortened to 98,304 steps
# the levels: kinetix generate --size s --count 256 --seed 0 --out /tmp/ab-levels
cd /work/main
K=.venv/bin/kinetix
for order in "1 2" "2 1"; do
for n in $order; do
  rm -rf /tmp/ab-p$n /tmp/ab-f$n
  s=$(date +%s.%N)
  KINETIX_CPU_DEVICES=$n $K pretrain --config experiments/cpu-small.yaml --run-dir /tmp/ab-p$n --levels /tmp/ab-levels --set ppo.total_timesteps=98304 --set run.eval_every=0 > /tmp/ab-p$n.log 2>&1
  m=$(date +%s.%N)
  KINETIX_CPU_DEVICES=$n $K finetune levels/m/two-link-reach.json --from general --run-dir /tmp/ab-f$n --config experiments/cpu-small.yaml --set ppo.total_timesteps=98304 --set run.eval_every=0 > /tmp/ab-f$n.log 2>&1
  e=$(date +%s.%N)
  echo "devices $n: pretrain $(echo "$m - $s" | bc) s ($(grep -o '[0-9,]* SPS' /tmp/ab-p$n.log | tail -1)), finetune $(echo "$e - $m" | bc) s ($(grep -o '[0-9,]* SPS' /tmp/ab-f$n.log | tail -1))"
done; done
