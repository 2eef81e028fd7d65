"""The experiment's settings: one frozen dataclass per YAML section (`env`, `model`, `ppo`, `run`, `levels`,
`curriculum`) and `ExperimentConfig`, the whole experiment. Each field has a docstring line with its unit and
reference value; each class checks its fields when built (`config.fields`). The choices of the string fields come
from `engine.SIZES` and `kinetix_cli.constants`, so they cannot drift from what the environment and the networks
accept."""

from __future__ import annotations

import dataclasses
from typing import ClassVar, Literal

from engine import SIZES
from kinetix_cli.config.fields import ConfigError, check_types, require, within
from kinetix_cli.constants import (
    ACTION_TYPES,
    COMPUTE_TYPES,
    EXPERIMENT_FORMAT,
    INT32_MAX,
    MODEL_NAMES,
    MODEL_OBSERVATIONS,
    NUM_ATTENTION_CHANNELS,
    OBSERVATION_TYPES,
    VALIDATION_SEED,
)

CONFIG_FORMAT = EXPERIMENT_FORMAT
CONFIG_FILENAME = "config.yaml"  # the resolved config saved in every run directory

# The choices of the string fields (a tuple subscript spells out a Literal of its items).
Size = Literal[tuple(SIZES)]
Observation = Literal[OBSERVATION_TYPES]
ActionKind = Literal[ACTION_TYPES]
ModelName = Literal[MODEL_NAMES]
WandbMode = Literal["off", "offline", "online"]
MirrorJoin = Literal["none", "mean", "geometric"]
ComputeType = Literal[COMPUTE_TYPES]
LevelSource = Literal["fresh", "generated", "levelset", "files"]
CurriculumName = Literal["dr", "sfl", "plr", "accel"]
PLRScore = Literal["maxmc", "pvl"]


@dataclasses.dataclass(frozen=True, kw_only=True)
class EnvSettings:
    """The environment every training env runs.

    Attributes:
        size: entity capacities 's', 'm' or 'l' (polygons/circles/joints/thrusters 5/2/1/1, 6/3/2/2, 12/4/6/2).
            Levels smaller than the size are padded up; a level too big for it is an error.
        observation: 'symbolic-entity' (per-entity features and attention masks; for 'transformer', 'pi-mlp' and
            'rel-mlp'),
            'symbolic-flat' (one vector) or 'pixels' (125 x 125 RGB); `constants.MODEL_OBSERVATIONS` says which
            model reads which.
        action: 'multi-discrete' (per binding: motor off/+1/-1, thruster off/on), 'discrete' (11 choices, one
            actuator at a time) or 'continuous' (6 values).
        dense_reward_scale: weight of the shaping term -(d_t - d_{t-1}) added to the reward, with d the summed
            green-blue centre distance [reward per metre]; 0 turns shaping off. (The reference configs use 0.2.)
        frame_skip: engine steps (dt = 1/60 s each) per environment step; the action is held for all of them.
        max_steps: episode cap [environment steps]; 256 at frame_skip 2 is ~8.5 s. A timeout truncates the episode
            (PPO bootstraps from the value of its last observation); it is not a failure.
    """

    SECTION: ClassVar[str] = "env"

    size: Size = "m"
    observation: Observation = "symbolic-entity"
    action: ActionKind = "multi-discrete"
    dense_reward_scale: float = 0.1
    frame_skip: int = 2
    max_steps: int = 256

    def __post_init__(self):
        check_types(self)
        within(self, "dense_reward_scale", 0, 1000)
        within(self, "frame_skip", 1, 1000)
        within(self, "max_steps", 1, INT32_MAX)


@dataclasses.dataclass(frozen=True, kw_only=True)
class ModelSettings:
    """The actor-critic network.

    Attributes:
        name: 'transformer' (entity transformer, size-independent, needs env.observation 'symbolic-entity'),
            'pi-mlp' (permutation-invariant MLP over entities, also 'symbolic-entity'), 'rel-mlp' (the same with
            actuators joined to their bodies, world-frame thrust, shapes relative to green and blue, and pooling by
            role and by action binding; 'symbolic-entity') or 'flat-mlp' (an MLP on 'symbolic-flat', or on the
            flattened 'pixels').
        width: hidden width of the entity encoders, transformer embedding and actor/critic layers [units].
        actor_critic_layers: hidden layers (tanh) in each of the actor and critic heads.
        transformer_layers: transformer blocks ('transformer' only).
        heads: attention heads per block ('transformer' only): a multiple of 4 (each of the 4 attention-mask
            channels drives heads / 4 of them); the head size is width / heads (128 / 8 = 16).
        mask_unused_actions: the action entries of bindings that no actuator of the level uses stay "off" and
            count in neither log-probability nor entropy (entity models only; off: the reference's policy).
        mirror: 'none', or how the model joins its view of each state with its view of the state's mirror image
            (the environment observes both): 'mean' of the two action probabilities or their 'geometric' mean, the
            value the mean of the two. Left-right equivariant by construction, in training too; the parameters are
            the plain model's (a plain agent starts such a run, and back). Two network calls a step.
        compute: the number type of the network's arithmetic: 'float32', or 'bfloat16' (mixed precision: the
            parameters, the optimiser's state, the loss and the distributions stay float32; the layers compute in
            bfloat16). Checkpoints are the same either way.
    """

    SECTION: ClassVar[str] = "model"

    name: ModelName = "transformer"
    width: int = 128
    actor_critic_layers: int = 5
    transformer_layers: int = 2
    heads: int = 8
    mask_unused_actions: bool = False
    mirror: MirrorJoin = "none"
    compute: ComputeType = "float32"

    @property
    def reads_pairs(self) -> bool:
        """Whether the model reads (observation, mirrored observation) pairs (`make_env(..., pairs=True)`)."""
        return self.mirror != "none"

    @property
    def reads_attention(self) -> bool:
        """Whether the model reads the entity observation's attention mask (`make_env(..., attention=True)`)."""
        return self.name == "transformer"

    def __post_init__(self):
        check_types(self)
        require(
            self,
            "mask_unused_actions",
            not (self.mask_unused_actions and self.name == "flat-mlp"),
            "needs an entity model (flat-mlp's input does not name the bindings)",
        )
        for name in ("width", "actor_critic_layers", "transformer_layers", "heads"):
            within(self, name, 1, 65536)
        if self.name == "transformer":
            require(self, "heads", self.width % self.heads == 0, f"width {self.width} is not divisible by heads")
            channels = NUM_ATTENTION_CHANNELS
            require(self, "heads", self.heads % channels == 0, f"must be a multiple of {channels} (attention channels)")


@dataclasses.dataclass(frozen=True, kw_only=True)
class PPOSettings:
    """PPO (PureJaxRL style). Defaults are the reference's.

    Attributes:
        num_envs: environments stepped in parallel.
        num_steps: environment steps per env per rollout; one update consumes num_envs * num_steps transitions.
        update_epochs: passes over each rollout.
        num_minibatches: minibatches per epoch; must divide num_envs * num_steps.
        gamma: discount per environment step.
        gae_lambda: GAE lambda.
        clip_eps: PPO ratio clip (also clips the value update).
        ent_coef: weight of the entropy bonus in the loss (at the first update, with `ent_coef_end`).
        ent_coef_end: null keeps `ent_coef` for the whole run; a number makes the weight move linearly from
            `ent_coef` at the first update to this at the last (fine-tuning: explore first, then settle).
        vf_coef: weight of the value loss.
        lr: Adam learning rate (the start value when anneal_lr).
        adam_eps: Adam epsilon.
        max_grad_norm: global gradient-norm clip.
        anneal_lr: decay lr linearly to 0 over the run; false keeps it constant (the reference).
        total_timesteps: environment steps of the whole run, over all envs (required); the run does
            total_timesteps // (num_envs * num_steps) updates.
        normalise_advantages: normalise advantages per minibatch (zero mean, unit std).
        mirror_coef: weight of a left-right symmetry loss (0: none): the mean KL divergence between the policy at
            each state and its own choice at the state's mirror image, mirrored back. The environment observes
            every state twice (as it is and mirrored); the network runs once a step in rollouts, and in updates
            once more on `mirror_share` of each minibatch. Trains a plain model (not with `model.mirror`,
            equivariant already).
        mirror_share: the share of each (shuffled) minibatch the symmetry loss is computed on, in (0, 1]: its
            cost in updates scales with it.
    """

    SECTION: ClassVar[str] = "ppo"

    num_envs: int = 2048
    num_steps: int = 64
    update_epochs: int = 8
    num_minibatches: int = 32
    gamma: float = 0.995
    gae_lambda: float = 0.9
    clip_eps: float = 0.2
    ent_coef: float = 0.01
    ent_coef_end: float | None = None
    vf_coef: float = 0.5
    lr: float = 5e-5
    adam_eps: float = 1e-5
    max_grad_norm: float = 1.0
    anneal_lr: bool = False
    total_timesteps: int
    normalise_advantages: bool = True
    mirror_coef: float = 0.0
    mirror_share: float = 1.0

    def __post_init__(self):
        check_types(self)
        for name in ("num_envs", "num_steps", "update_epochs", "num_minibatches"):
            within(self, name, 1, INT32_MAX)
        for name in ("gamma", "gae_lambda"):
            within(self, name, 0, 1)
        for name, high in (("lr", 1), ("adam_eps", 1), ("clip_eps", 10), ("max_grad_norm", 1e6)):
            within(self, name, 0, high, low_excluded=True)
        for name in ("ent_coef", "vf_coef", "mirror_coef"):
            within(self, name, 0, 1000)
        within(self, "mirror_share", 0, 1, low_excluded=True)
        if self.ent_coef_end is not None:
            within(self, "ent_coef_end", 0, 1000)
        batch = f"num_envs * num_steps = {self.num_envs} * {self.num_steps} = {self.batch_size}"
        require(self, "num_minibatches", self.batch_size % self.num_minibatches == 0, f"{batch} is not divisible by it")
        require(self, "total_timesteps", self.total_timesteps >= self.batch_size, f"is less than one update ({batch})")
        within(self, "total_timesteps", 1, 10**15)

    @property
    def batch_size(self) -> int:
        """Transitions per update: num_envs * num_steps."""
        return self.num_envs * self.num_steps

    @property
    def minibatch_size(self) -> int:
        """Transitions per minibatch."""
        return self.batch_size // self.num_minibatches

    @property
    def mirror_batch(self) -> int:
        """Transitions of each minibatch the symmetry loss is computed on (at least 1)."""
        return max(1, round(self.mirror_share * self.minibatch_size))

    @property
    def num_updates(self) -> int:
        """Updates in the run: total_timesteps // batch_size."""
        return self.total_timesteps // self.batch_size


@dataclasses.dataclass(frozen=True, kw_only=True)
class RunSettings:
    """Bookkeeping of one run.

    Attributes:
        seed: PRNG seed of the whole run (levels, policy sampling, initial parameters).
        checkpoint_every: save a checkpoint every this many updates [updates]; 0 saves only at the end.
        eval_every: evaluate the policy on `eval_levels` every this many updates, and after the last one
            [updates]; 0 never. The solve rate goes into metrics.jsonl as `eval_solve_rate` (mean over levels).
        eval_attempts: stochastic attempts per evaluation level.
        eval_levels: level files or folders to evaluate on during training (e.g. levels/s); empty: no evaluation.
            `kinetix finetune` sets it to its fine-tuning levels (a `--set run.eval_levels=...` still wins).
        wandb: Weights & Biases logging: 'off' (default), 'offline' (local files to sync later) or 'online'.
        init_from: checkpoint to load the initial parameters from (fine-tuning), or null to start from scratch.
        fresh_policy_head: fine-tuning only (with `init_from` or `kinetix finetune --from`): the actor's output
            layer starts freshly initialised, a near-uniform policy, while the rest of the network (features, critic)
            keeps the loaded parameters; for agents whose confident habits fail on the new level.
        policy_temperature: fine-tuning only, discrete actions: the loaded actor's logits are divided by this at
            the start (its output layer's weights and bias scaled by 1 / this), so a near-deterministic agent
            explores again while its preferences keep their order; 1 (default) loads the actor as it is.
        fresh_critic: fine-tuning only: the critic (its MLP and output layer) starts freshly initialised while the
            shared features and the actor keep the loaded parameters; the loaded value estimates were learned on
            other levels.
        restart_unsolved_after: fine-tuning only: if no training episode was solved in the first this many updates,
            the run starts again from the loaded features alone (a fresh policy head and critic, a new optimiser
            state) for the rest of its budget, logging `restarted` at that update: for levels where the loaded
            habit finds no reward [updates]; 0 (default): never.
        minutes: a wall-clock budget [min]: the run ends after the update during which its training time (the
            updates' own seconds, curriculum scoring included, evaluations and checkpoints not) passes it, with a
            checkpoint and an evaluation as at the end; `ppo.total_timesteps` still caps it. 0: no budget. For
            comparisons at equal wall-clock; the learning-rate schedule still runs over `ppo.total_timesteps`.
            The one setting a resumed run may change: `--resume --set run.minutes=...` extends the budget.
    """

    SECTION: ClassVar[str] = "run"

    seed: int = 0
    checkpoint_every: int = 100
    eval_every: int = 100
    eval_attempts: int = 50
    eval_levels: tuple[str, ...] = ()
    wandb: WandbMode = "off"
    init_from: str | None = None
    fresh_policy_head: bool = False
    policy_temperature: float = 1.0
    fresh_critic: bool = False
    restart_unsolved_after: int = 0
    minutes: float = 0.0

    def __post_init__(self):
        check_types(self)
        within(self, "seed", 0, VALIDATION_SEED - 1)  # the seeds above are the validation suite's
        within(self, "minutes", 0, 10**7)  # 0: no budget
        require(self, "fresh_policy_head", self.init_from or not self.fresh_policy_head, "needs run.init_from")
        require(self, "fresh_critic", self.init_from or not self.fresh_critic, "needs run.init_from")
        within(self, "restart_unsolved_after", 0, INT32_MAX)  # 0: never
        restarts = bool(self.restart_unsolved_after)
        require(self, "restart_unsolved_after", self.init_from or not restarts, "needs run.init_from")
        within(self, "policy_temperature", 1e-3, 1e3)
        if self.policy_temperature != 1.0:
            require(self, "policy_temperature", self.init_from, "needs run.init_from")
            require(
                self,
                "policy_temperature",
                not self.fresh_policy_head,
                "softens a loaded actor; with run.fresh_policy_head there is none",
            )
        within(self, "checkpoint_every", 0, INT32_MAX)  # 0: only at the end
        within(self, "eval_every", 0, INT32_MAX)  # 0: never
        within(self, "eval_attempts", 1, 10**6)


@dataclasses.dataclass(frozen=True, kw_only=True)
class LevelSettings:
    """Where the training levels come from. Paths are relative to the working directory.

    Attributes:
        source: 'fresh' (levels on the fly: every update samples `num_envs` new random levels inside the jitted
            training step, and its episodes restart from them; the reference's default), 'generated'
            (`pool_size` random levels sampled once at the start and held in a pool on the device), 'levelset'
            (a level set directory written by `kinetix generate`: a fixed, reproducible set, filtered by no-op
            and random play) or 'files' (level files, e.g. for fine-tuning).
        levelset: the level set directory (source 'levelset' only), else null.
        solved_only: source 'levelset' with a solved set (`kinetix levels solve`): train only on the levels its
            search solved, leaving out those it marked unsolved.
        files: level files (`kinetix-level/1` JSON) to train on (source 'files' only), else empty.
        pool_size: generated levels held on the device (source 'generated'), sampled and filtered once at the start
            of the run with the run's seed; episodes reset to a uniformly drawn pool level.
        pool_chunk: levels sampled and filtered per device batch while the pool is generated (as `kinetix
            generate --chunk`; the pool is the first `pool_size` levels kept from chunks 0, 1, ...).
        refresh_every: source 'generated': every this many updates the pool is replaced by `pool_size` new
            filtered levels (round r = update // refresh_every, its own seed), so a run sees an endless stream of
            levels that no-op and random play do not solve, at the cost of one pool's generation per round; 0:
            the pool is generated once.
        fresh_like: source 'fresh': draw each level like one of these sizes (equal shares) in `env.size`'s slots:
            `[s, m]` at size m trains one agent on s- and m-like levels at once. Empty: like `env.size`.
    """

    SECTION: ClassVar[str] = "levels"

    source: LevelSource = "generated"
    levelset: str | None = None
    solved_only: bool = False
    files: tuple[str, ...] = ()
    pool_size: int = 4096
    pool_chunk: int = 1024
    refresh_every: int = 0
    fresh_like: tuple[str, ...] = ()

    def __post_init__(self):
        check_types(self)
        within(self, "pool_size", 1, 10**8)
        if self.fresh_like:
            require(self, "fresh_like", self.source == "fresh", "is only used when levels.source is 'fresh'")
            unknown = [n for n in self.fresh_like if n not in SIZES]
            require(self, "fresh_like", not unknown, f"names no size {unknown}; choose among {', '.join(SIZES)}")
        within(self, "pool_chunk", 1, 2**20)
        within(self, "refresh_every", 0, 10**9)
        if self.refresh_every:
            require(self, "refresh_every", self.source == "generated", "is only used when levels.source is 'generated'")
        if self.solved_only:
            require(self, "solved_only", self.source == "levelset", "is only used when levels.source is 'levelset'")
        if self.source == "levelset":
            require(self, "levelset", self.levelset is not None, "is required when levels.source is 'levelset'")
        else:
            require(self, "levelset", self.levelset is None, "is only used when levels.source is 'levelset'")
        if self.source == "files":
            require(
                self, "files", len(self.files) > 0, "must list at least one level file when levels.source is 'files'"
            )
        else:
            require(self, "files", not self.files, "is only used when levels.source is 'files'")


@dataclasses.dataclass(frozen=True, kw_only=True)
class CurriculumSettings:
    """Which of the source's levels the training episodes start from (`--set curriculum.name=sfl` switches).

    Attributes:
        name: 'dr' (domain randomisation: uniformly from the level source; the baseline), 'sfl' (sampling for
            learnability, `rl.curricula.sfl`: every `refresh_every` updates the current policy plays
            `score_levels` levels drawn from the source, `score_attempts` copies of each for `score_steps`
            steps; the `buffer_size` most learnable (p (1 - p), p the solve rate) form the buffer, and each update
            restarts a `buffer_share` of its episodes from them, the rest from the source) or 'plr' (robust
            prioritised level replay, `rl.curricula.plr`: every update resets all environments; with probability
            `replay_prob` they replay buffer levels, sampled by score rank and staleness, and train on them;
            otherwise they play new levels from the source without training, only to score them, and the
            best-scoring levels stay in the buffer of `buffer_size`) or 'accel' (PLR whose candidates are also
            mutations of buffer levels: `edits` random edits each, `generator.mutate`).
        score_levels: SFL: levels scored per refresh (reference 12,288 = 3 x 4,096).
        score_batch: SFL: levels drawn from one key while scoring (bounds the generator's memory; divides
            `score_levels`); all `score_levels` x `score_attempts` copies are then played at once.
        score_steps: SFL: environment steps each copy of a scored level is played for [steps] (reference 512).
        score_attempts: SFL: copies of each scored level played side by side (reference 1: its 512 steps hold
            two or more episodes of at most 256 steps); with `score_steps` equal to `env.max_steps`, at least this
            many episodes decide p.
        buffer_size: levels the buffer holds (reference: SFL 1,024, PLR 4,000).
        refresh_every: SFL: updates between refreshes of the buffer [updates] (reference 128); the first is
            before the first update.
        buffer_share: SFL: share of each update's episodes that start from buffer levels (reference 0.5).
        replay_prob: PLR: probability that an update replays buffer levels (reference 0.5).
        staleness: PLR: weight of staleness (updates since a level was last played) against score rank in the
            replay distribution (reference 0.3).
        temperature: PLR: the score part of the replay distribution is proportional to rank^(-1/temperature).
        plr_score: PLR: a level's score, 'maxmc' (mean over the rollout of the best return seen on the level
            minus the value estimate; the reference's) or 'pvl' (mean positive GAE advantage).
        min_fill: PLR: share of the buffer that must hold levels before updates replay them.
        edits: ACCEL: random edits per mutated level.
    """

    SECTION: ClassVar[str] = "curriculum"

    name: CurriculumName = "dr"
    score_levels: int = 12_288
    score_batch: int = 4_096
    score_steps: int = 512
    score_attempts: int = 1
    buffer_size: int = 1_024
    refresh_every: int = 128
    buffer_share: float = 0.5
    replay_prob: float = 0.5
    staleness: float = 0.3
    temperature: float = 0.3
    plr_score: PLRScore = "maxmc"
    min_fill: float = 0.5
    edits: int = 5

    def __post_init__(self):
        check_types(self)
        within(self, "score_levels", 1, 2**24)
        within(self, "score_batch", 1, 2**24)
        within(self, "score_steps", 1, 10**5)
        within(self, "score_attempts", 1, 1024)
        within(self, "buffer_size", 1, 2**24)
        within(self, "refresh_every", 1, INT32_MAX)
        within(self, "buffer_share", 0.0, 1.0, low_excluded=True)
        require(self, "score_batch", self.score_levels % self.score_batch == 0, "must divide curriculum.score_levels")
        within(self, "replay_prob", 0.0, 1.0)
        within(self, "staleness", 0.0, 1.0)
        within(self, "temperature", 0.0, 100.0, low_excluded=True)
        within(self, "min_fill", 0.0, 1.0)
        within(self, "edits", 1, 100)
        if self.name == "sfl":
            require(self, "buffer_size", self.buffer_size <= self.score_levels, "must be <= curriculum.score_levels")

    @property
    def scoring_steps(self) -> int:
        """Environment steps of one refresh: score_levels x score_attempts x score_steps (0 for 'dr')."""
        return self.score_levels * self.score_attempts * self.score_steps if self.name == "sfl" else 0


@dataclasses.dataclass(frozen=True, kw_only=True)
class CloneSettings:
    """Learning from solved levels (`rl.clone`): behaviour cloning of the solutions in a solved level set (`kinetix
    levels solve`), before PPO and/or beside it. Each cloning step replays `batch` solved levels with their stored
    actions (observations are replayed, not stored) and takes one Adam step on the mean negative log-likelihood of
    those actions over the steps before each solve. Unsolved levels of the set are left out.

    Attributes:
        levels: the solved level set directory, or null (no cloning). Its levels may be of another size than
            `env.size` when the observation plays every size (`symbolic-entity`); its solutions were found with
            `env.frame_skip` 2 and multi-discrete actions, which the run must share.
        updates: cloning steps before the first PPO update [steps] (a fresh Adam of `lr`; PPO then starts with a
            fresh optimiser state). Counted in `run.minutes`.
        coef: after every PPO update, one cloning step of this weight on the PPO optimiser (PPO with a cloning
            loss, alternating); 0: none.
        batch: solved levels replayed per cloning step (each drawn uniformly with replacement) [levels].
        lr: learning rate of the cloning steps before PPO.
    """

    SECTION: ClassVar[str] = "clone"

    levels: str | None = None
    updates: int = 0
    coef: float = 0.0
    batch: int = 32
    lr: float = 3e-4

    def __post_init__(self):
        check_types(self)
        within(self, "updates", 0, 10**7)
        within(self, "coef", 0.0, 1e3)
        within(self, "batch", 1, 2**16)
        within(self, "lr", 0.0, 1.0, low_excluded=True)
        if self.levels is None:
            require(self, "updates", self.updates == 0, "needs clone.levels")
            require(self, "coef", self.coef == 0, "needs clone.levels")
        else:
            require(self, "levels", self.updates > 0 or self.coef > 0, "is unused unless clone.updates or clone.coef")

    @property
    def active(self) -> bool:
        """Whether the run clones at all."""
        return self.levels is not None


@dataclasses.dataclass(frozen=True, kw_only=True)
class ExperimentConfig:
    """A whole experiment: one field per YAML section.

    Attributes:
        env: the environment (`EnvSettings`).
        model: the network (`ModelSettings`).
        ppo: the PPO hyperparameters and budget (`PPOSettings`).
        run: seed, checkpoints, evaluation and logging (`RunSettings`).
        levels: the training levels (`LevelSettings`).
        curriculum: which of them episodes start from (`CurriculumSettings`).
        clone: behaviour cloning of solved levels (`CloneSettings`).
    """

    env: EnvSettings = dataclasses.field(default_factory=EnvSettings)
    model: ModelSettings = dataclasses.field(default_factory=ModelSettings)
    ppo: PPOSettings
    run: RunSettings = dataclasses.field(default_factory=RunSettings)
    levels: LevelSettings = dataclasses.field(default_factory=LevelSettings)
    curriculum: CurriculumSettings = dataclasses.field(default_factory=CurriculumSettings)
    clone: CloneSettings = dataclasses.field(default_factory=CloneSettings)

    def __post_init__(self):
        check_types(self)
        if self.curriculum.name == "sfl" and round(self.curriculum.buffer_share * self.ppo.num_envs) == 0:
            raise ConfigError(
                f"curriculum.buffer_share: {self.curriculum.buffer_share:g} of ppo.num_envs {self.ppo.num_envs} "
                "is no environment; raise either"
            )
        if self.curriculum.name in ("plr", "accel") and self.ppo.num_steps < self.env.max_steps:
            raise ConfigError(
                f"ppo.num_steps: {self.ppo.num_steps} is shorter than env.max_steps {self.env.max_steps}; "
                f"{self.curriculum.name!r} resets every environment at each update, so a shorter rollout would cut "
                "every episode"
            )
        if self.ppo.mirror_coef and self.model.reads_pairs:
            raise ConfigError(
                f"ppo.mirror_coef: model.mirror {self.model.mirror!r} is left-right equivariant already (the loss "
                "would be 0); train a plain model with it"
            )
        allowed = MODEL_OBSERVATIONS[self.model.name]
        if self.env.observation not in allowed:
            raise ConfigError(
                f"model.name: {self.model.name!r} needs env.observation {' or '.join(map(repr, allowed))}, "
                f"got {self.env.observation!r}"
            )
        if self.run.policy_temperature != 1.0 and self.env.action not in ("multi-discrete", "discrete"):
            raise ConfigError(
                f"run.policy_temperature: softens discrete actions' logits; env.action {self.env.action!r} has none"
            )
        if self.run.restart_unsolved_after >= self.ppo.num_updates:
            raise ConfigError(
                f"run.restart_unsolved_after: {self.run.restart_unsolved_after} updates is not before the run's last "
                f"({self.ppo.num_updates}, from ppo.total_timesteps); a restart there would never train"
            )
        order = list(SIZES)
        larger = [n for n in self.levels.fresh_like if order.index(n) > order.index(self.env.size)]
        if larger:
            raise ConfigError(
                f"levels.fresh_like: {larger} are larger than env.size {self.env.size!r}; a level is drawn in the "
                "slots of env.size, so raise env.size to the largest"
            )

    @property
    def trains_on_pairs(self) -> bool:
        """Whether training observes every state and its mirror image (`make_env(..., pairs=True)`): the model
        joins the two (`model.mirror`) or the symmetry loss compares them (`ppo.mirror_coef`)."""
        return self.model.reads_pairs or self.ppo.mirror_coef > 0


SECTIONS: dict[str, type] = {
    "env": EnvSettings,
    "model": ModelSettings,
    "ppo": PPOSettings,
    "run": RunSettings,
    "levels": LevelSettings,
    "curriculum": CurriculumSettings,
    "clone": CloneSettings,
}
