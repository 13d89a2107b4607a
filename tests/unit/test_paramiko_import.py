"""paramiko without invoke at start-up; ssh_config's Match exec still works (invoke then loads)."""

from __future__ import annotations

import subprocess
import sys
import textwrap


def test_paramiko_loads_without_invoke_and_match_exec_still_works() -> None:
    code = textwrap.dedent("""
        import sys
        from panther_ops.transport.paramiko_import import import_paramiko
        paramiko = import_paramiko()
        assert "invoke" not in sys.modules, "invoke imported with paramiko"
        assert import_paramiko() is paramiko
        conf = paramiko.SSHConfig.from_text('Match exec "true"\\n  User bob\\nMatch exec "false"\\n  Port 2\\n')
        got = conf.lookup("robot")
        assert got.get("user") == "bob" and "port" not in got, got
        assert "invoke" in sys.modules, "Match exec loads invoke on demand"
        print("ok")
    """)
    proc = subprocess.run([sys.executable, "-c", code], check=False, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "ok"


def test_invoke_already_loaded_is_left_alone() -> None:
    code = textwrap.dedent("""
        import sys, invoke
        from panther_ops.transport.paramiko_import import import_paramiko
        paramiko = import_paramiko()
        assert paramiko.config.invoke is invoke
        print("ok")
    """)
    proc = subprocess.run([sys.executable, "-c", code], check=False, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr


def test_paramiko_knows_its_version_without_importlib_metadata() -> None:
    code = textwrap.dedent("""
        import sys
        from panther_ops.transport.paramiko_import import import_paramiko
        paramiko = import_paramiko()
        assert "importlib.metadata" not in sys.modules, "the stand-in is gone, the real module not loaded"
        import importlib.metadata
        assert type(importlib.metadata).__name__ == "module"
        assert paramiko.__version__ == importlib.metadata.version("paramiko")
        print("ok")
    """)
    proc = subprocess.run([sys.executable, "-c", code], check=False, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "ok"


def test_quick_metadata_defers_what_it_does_not_know() -> None:
    from panther_ops.transport.paramiko_import import _dist_versions, _QuickMetadata

    versions = _dist_versions("paramiko")
    import importlib.metadata

    assert versions["paramiko"] == importlib.metadata.version("paramiko")
    quick = _QuickMetadata({})
    assert quick.version("PyYAML") == importlib.metadata.version("PyYAML")
    assert quick.PackageNotFoundError is importlib.metadata.PackageNotFoundError
