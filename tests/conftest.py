import os

import pytest

os.environ.setdefault("MS_RENDERER_LOG_LEVEL", "error")

import gymnasium as gym  # noqa: E402

import dynnav_tasks  # noqa: E402


@pytest.fixture
def make_env():
    """Make a task wrapped for plain gymnasium use (``NumpyWrapper``: numpy, unbatched); closed
    after the test."""
    made = []

    def _make(task_id, **kwargs):
        env = dynnav_tasks.NumpyWrapper(gym.make(task_id, **kwargs))
        made.append(env)
        return env

    yield _make
    for env in made:
        env.close()


@pytest.fixture(params=dynnav_tasks.TASK_IDS)
def task_id(request):
    return request.param
