"""Launch-free node testing: one rclpy Context per test, spun in the test's own thread."""
import time
from contextlib import contextmanager

import rclpy
from rclpy.executors import SingleThreadedExecutor


class Harness:
    def __init__(self, context):
        self.context = context
        self.executor = SingleThreadedExecutor(context=context)
        self.nodes = []

    def add(self, node):
        self.nodes.append(node)
        self.executor.add_node(node)
        return node

    def spin_for(self, seconds):
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            self.executor.spin_once(timeout_sec=0.005)

    def spin_until(self, predicate, timeout=5.0):
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            if predicate():
                return True
            self.executor.spin_once(timeout_sec=0.005)
        return predicate()

    def call(self, client, request, timeout=5.0):
        assert client.wait_for_service(timeout_sec=timeout), client.srv_name
        future = client.call_async(request)
        assert self.spin_until(future.done, timeout), f"no response from {client.srv_name}"
        return future.result()


@contextmanager
def ros():
    context = rclpy.Context()
    rclpy.init(context=context)
    harness = Harness(context)
    try:
        yield harness
    finally:
        for node in harness.nodes:
            harness.executor.remove_node(node)
            node.destroy_node()
        harness.executor.shutdown()
        rclpy.shutdown(context=context)
