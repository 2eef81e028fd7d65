set -e
for side in after before; do
  tree=/work/base-clone; [ "$side" = after ] && tree=/work/main
  rm -rf /work/ba/run-$side-3
  (cd $tree && .venv/bin/kinetix pretrain --config experiments/general.yaml --run-dir /work/ba/run-$side-3 --set ppo.total_timesteps=262144 --set run.eval_every=0 --set run.checkpoint_every=8 > /dev/null 2>&1)
  cp /work/ba/run-$side-3/metrics.jsonl /work/ba/metrics-$side-3.jsonl; rm -rf /work/ba/run-$side-3
done
python3 -c "
import json,statistics
for s in ('after','before'):
    l=[json.loads(x) for x in open(f'/work/ba/metrics-{s}-3.jsonl')]
    print(s, 3, round(statistics.median(r['sps'] for r in l[1:])), round(8192/l[0]['sps'],1))
"
