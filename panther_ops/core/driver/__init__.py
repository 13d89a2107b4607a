"""`panther-ops driver ...` and `config restore-defaults`: the driver container and its image.

Modules: ``images`` (image references, tags, Docker Hub's released tags), ``containers``
(status, logs, versions as the engine shows them); ``plan`` (the pure planners of restart,
stop/start, update and config restore-defaults), ``read`` (what they read) and ``apply``
(their executors). Every robot step goes through the
robot's transport: the docker SDK rides its one SSH connection (`Transport.docker`), and
``docker compose`` runs as the robot user in a login shell, as Husarion's tools do. Changes
to compose.yaml go through the apply pipeline (`pipeline.apply_plan`); what it has no slot for
is a typed step of the plan (`plan.py`: pull before recreating and removing the container of a
renamed service, `UpdateDriver`; the 2.2 config tree reset, `ResetConfigTree`; a restart, a
stop or start), carried out by `apply.py`'s executors, which roll back the same way.

The one operator-side effect is `hub.fetch_hub_tags`: an HTTPS GET to Docker Hub from this
machine (robots usually have no route to the internet, ``transport.http_json``), with a short timeout.
"""
