set -e
SETS="--set levels.source=files --set levels.files=[levels/s/rocket-car-jump.json,levels/s/pad-to-pad.json] --set env.frame_skip=4 --set model.width=16 --set model.actor_critic_layers=1 --set ppo.num_envs=8 --set ppo.num_steps=8 --set ppo.num_minibatches=2 --set ppo.update_epochs=1 --set ppo.total_timesteps=64000 --set run.checkpoint_every=0 --set run.eval_every=0"
for side in before after after before before after; do
  tree=/work/base-clone; [ "$side" = after ] && tree=/work/main
  rm -rf /work/ba/tiny-$side
  (cd $tree && .venv/bin/kinetix pretrain --config experiments/cpu-small.yaml --run-dir /work/ba/tiny-$side $SETS > /dev/null 2>&1)
  python3 -c "
import json,statistics
l=[json.loads(x) for x in open('/work/ba/tiny-$side/metrics.jsonl')]
s=[64/r['sps']*1000 for r in l[1:]]
print('$side', len(l), 'median ms/update', round(statistics.median(s),3), 'mean', round(statistics.mean(s),3))
" | tee -a /work/ba/tiny.txt
done
